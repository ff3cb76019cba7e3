#include "retarget/passes/com_replan.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/balance/com_motion.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/flat_contact.hpp"

namespace rt {

ComReplanPlan plan_com(const BalanceController& balance, const ComReplanOptions& o, const Eigen::Matrix2Xd& com_W,
                       const std::function<const SupportFrame&(int)>& support, const ComPreviewOptions& preview) {
  const int K = static_cast<int>(com_W.cols());
  RT_DEMAND(K > 0, "plan_com: empty COM trajectory");
  const int N = o.horizon;
  const ClosedLoopModel model = balance.closed_loop_model(o.period_s);
  const ComReplanner planner(model, o);
  const double omega_sq = balance.model().omega_sq();
  ComReplanPlan plan;
  plan.period_s = o.period_s;
  plan.com_original_W = com_W;
  plan.cop_predicted_W.resize(2, K);
  plan.com_predicted_W.resize(2, K);
  plan.com_replanned_W.resize(2, K);

  if (!preview.feedforward) {
    // The paper's regulator: the model state x is absolute, U the reference COM itself, padded with
    // its last value so every window holds N steps.
    Eigen::Matrix2Xd U(2, K + N);
    U.leftCols(K) = com_W;
    for (int k = K; k < K + N; ++k) U.col(k) = com_W.col(K - 1);
    Mat42 x = balance.rest_state(com_W.col(0)).s_hat;
    for (int k = 0; k < K; ++k) {
      auto window = U.middleCols(k, N);
      const auto event = planner.step(x, window, [&](int j) -> const SupportFrame& { return support(k + j); });
      if (event) plan.events.emplace_back(k * o.period_s, *event);
      plan.cop_predicted_W.col(k) = (model.C * x).transpose();
      plan.com_predicted_W.col(k) = x.row(0).transpose();
      x = model.A * x + model.B * U.col(k).transpose();
    }
    plan.com_replanned_W = U.leftCols(K);
    return plan;
  }

  // Feed-forward (balance_controller.hpp): the model runs in error coordinates e = s − s_ref, the
  // planner's input U is the change δ of the COM reference (zero until re-planning adds some), and
  // the reference COP p_ref (the ZMP of the reference COM motion) is the known part of the output.
  // Without activations e stays 0: the model reproduces the reference COM exactly.
  const std::array<Eigen::Matrix2Xd, 4> d = com_derivatives(com_W, 1.0 / o.period_s, preview.com_smoothing_s);
  Eigen::Matrix2Xd p_ref(2, K);
  for (int k = 0; k < K; ++k) {
    Eigen::Matrix<double, 5, 2> motion;
    motion.row(0) = com_W.col(k).transpose();
    for (int i = 0; i < 4; ++i) motion.row(i + 1) = d[static_cast<std::size_t>(i)].col(k).transpose();
    p_ref.col(k) = BalanceReference::from_com_motion(motion, omega_sq).cop();
  }
  Eigen::Matrix2Xd U = Eigen::Matrix2Xd::Zero(2, K + N);
  Eigen::Matrix2Xd y_offset(2, N);
  Mat42 e = Mat42::Zero();
  for (int k = 0; k < K; ++k) {
    for (int j = 0; j < N; ++j) y_offset.col(j) = p_ref.col(std::min(k + j + 1, K - 1));
    auto window = U.middleCols(k, N);
    const auto event =
        planner.step(e, window, [&](int j) -> const SupportFrame& { return support(k + j); }, &y_offset);
    if (event) plan.events.emplace_back(k * o.period_s, *event);
    plan.cop_predicted_W.col(k) = p_ref.col(k) + (model.C * e).transpose();
    plan.com_predicted_W.col(k) = com_W.col(k) + e.row(0).transpose();
    e = model.A * e + model.B * U.col(k).transpose();
  }
  plan.com_replanned_W = com_W + U.leftCols(K);
  return plan;
}

ComReplanPass::ComReplanPass() {
  table_.add("horizon", options_.replan.horizon, "N: prediction window in model steps", {1, 2000, "steps"});
  table_.add("period", options_.replan.period_s, "[s] discretisation of the balance model (eq. 25)", {0.001, 0.1, "s"});
  table_.add("h_max", options_.replan.h_max, "eq. 33/34: how close to the polygon border the desired COP may be");
  table_.add("w", options_.replan.w, "eq. 31: W_ii = w i^2");
  table_.add("margin", options_.replan.margin_m, "[m] the predicted COP must stay this far inside the polygon");
  table_.add("feedforward", options_.preview.feedforward, "preview the balance controller with feed-forward (as the check runs it)");
  table_.add("com_smoothing", options_.preview.com_smoothing_s, "[s] Gaussian smoothing of the COM before its derivatives (feed-forward)",
             {0, 1, "s"});
  table_.add("max_shift", options_.max_shift_m, "[m] largest COM shift given to the COM-following IK (longer ones are clipped)");
  table_.add("velocity_margin", options_.velocity_margin, "fraction of each velocity limit the COM-following steps keep free");
  table_.add("foot_tolerance", options_.foot_tolerance_m, "[m] how far a held sole may move before a shift is halved");
  table_.add("foot_tolerance_angle", options_.foot_tolerance_rad, "[rad] how far a held sole may turn before a shift is halved");
  table_.add("com_weight", options_.com_weight, "COM-following IK: weight of the COM target");
  table_.add("foot_weight", options_.foot_weight, "COM-following IK: weight holding the feet");
  table_.add("posture_regularization", options_.posture_regularization, "COM-following IK: pull towards the frame's pose");
  table_.add("min_shift", options_.min_shift_m, "[m] frames whose COM moves less keep their pose");
}

void ComReplanPass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  RobotMotion& motion = clip.motion;
  const int T = motion.num_frames();
  if (T == 0) throw InputError("--passes", "com-replan needs the robot motion of the ik pass: put ik before com-replan");
  const double fps = motion.fps;

  // Per source frame: COM, sole frames, support polygon.
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  Mat3X com(3, T);
  std::vector<std::array<Iso3, 2>> soles(static_cast<std::size_t>(T));
  std::vector<SupportFrame> support(static_cast<std::size_t>(T));
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, motion.q.col(f));
    com.col(f) = com_position(model, data);
    std::vector<Vec2> corners;
    SupportFrame& s = support[static_cast<std::size_t>(f)];
    for (int foot = 0; foot < 2; ++foot) {
      const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
      const Iso3 X_link = link_pose(model, data, sole.link);
      Iso3 X = Iso3::Identity();
      X.linear() = X_link.linear() * R_L_sole[static_cast<std::size_t>(foot)];
      X.translation() = X_link * sole.p_L_center;
      soles[static_cast<std::size_t>(f)][static_cast<std::size_t>(foot)] = X;
      const bool down = clip.contacts.empty() || clip.contacts.in_contact[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)];
      s.contact[static_cast<std::size_t>(foot)] = down;
      s.sole_center_W[static_cast<std::size_t>(foot)] = X.translation().head<2>();
      if (down)
        for (const Vec3& c : sole.corners_L()) corners.push_back((X_link * c).head<2>());
    }
    s.polygon = SupportPolygon::convex_hull(std::move(corners));
  }

  // Planner grid.
  const double dt = options_.replan.period_s;
  const double duration = (T - 1) / fps;
  const int K = static_cast<int>(std::floor(duration / dt + 1e-9)) + 1;
  auto frame_at = [&](double t) { return std::clamp(static_cast<int>(std::lround(t * fps)), 0, T - 1); };
  Eigen::Matrix2Xd com_grid(2, K);
  for (int k = 0; k < K; ++k) {
    const double s = std::min(k * dt * fps, static_cast<double>(T - 1));
    const int i = std::min(static_cast<int>(s), T - 1), j = std::min(i + 1, T - 1);
    com_grid.col(k) = ((1 - (s - i)) * com.col(i) + (s - i) * com.col(j)).head<2>();
  }
  const BalanceController balance(PendulumModel{model.standing_com_height_m(), 9.81}, options_.balance);
  const ComReplanPlan plan = plan_com(
      balance, options_.replan, com_grid,
      [&](int k) -> const SupportFrame& { return support[static_cast<std::size_t>(frame_at(k * dt))]; },
      options_.preview);

  // Back to source frames.
  auto grid_at = [&](const Eigen::Matrix2Xd& g, double t) -> Vec2 {
    const double s = std::clamp(t / dt, 0.0, static_cast<double>(K - 1));
    const int i = std::min(static_cast<int>(s), K - 1), j = std::min(i + 1, K - 1);
    return (1 - (s - i)) * g.col(i) + (s - i) * g.col(j);
  };
  clip.com_replanned_W.resize(3, T);
  clip.cop_predicted_W.resize(2, T);
  // A shift beyond max_shift_m is clipped to it: with the feet held, the COM-following IK cannot
  // move the COM much further without dragging the feet, and a plan that needs more says the motion
  // is beyond this robot's balance (the dynamics check reports it).
  double max_shift = 0, max_planned_shift = 0;
  int clipped = 0;
  for (int f = 0; f < T; ++f) {
    Vec2 shift = grid_at(plan.com_predicted_W, f / fps) - com.col(f).head<2>();
    max_planned_shift = std::max(max_planned_shift, shift.norm());
    if (shift.norm() > options_.max_shift_m) {
      shift *= options_.max_shift_m / shift.norm();
      ++clipped;
    }
    clip.com_replanned_W.col(f) << com.col(f).head<2>() + shift, com(2, f);
    clip.cop_predicted_W.col(f) = grid_at(plan.cop_predicted_W, f / fps);
    max_shift = std::max(max_shift, shift.norm());
  }

  // COM-following IK: feet held where they are, COM pulled onto the re-planned COM. Frames whose COM
  // barely moves are left alone; the others start from the previous frame's correction, which is
  // nearly the answer (the correction varies slowly), so a few iterations suffice. Each frame's
  // joint change from the previous (final) frame is then rate-limited to the URDF velocity limits
  // (less velocity_margin), or to the original motion's own step where that was faster: the
  // correction must not make the motion infeasible to play, and the passes before it (refine) left
  // it within the limits.
  double max_residual = 0;
  int adjusted = 0, rate_limited = 0, dropped = 0;
  if (!plan.events.empty()) {
    IkOptions o;
    o.max_iterations = options_.ik_iterations;
    o.regularization = options_.posture_regularization;
    o.step_tolerance = 1e-5;
    o.cost_tolerance = 1e-4;
    const LandmarkIk ik(model, o);
    const MatX q_original = motion.q;
    const VecX& v_max = model.velocity_limits();
    VecX correction = VecX::Zero(model.nv());  // last frame's q_solved ⊖ q_frame
    std::vector<IkTarget> feet(2);
    for (int f = 0; f < T; ++f) {
      const VecX q_frame = q_original.col(f);
      const Vec3 target = clip.com_replanned_W.col(f);
      VecX q = q_frame;
      bool shift = (target - com.col(f)).head<2>().norm() >= options_.min_shift_m;
      if (shift) {
        for (int foot = 0; foot < 2; ++foot) {
          const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
          const Iso3& X = soles[static_cast<std::size_t>(f)][static_cast<std::size_t>(foot)];
          IkTarget& t = feet[static_cast<std::size_t>(foot)];
          t.link = sole.link;
          t.p_L = sole.p_L_center;
          t.p_W = X.translation();
          t.weight = options_.foot_weight;
          t.R_L_frame = R_L_sole[static_cast<std::size_t>(foot)];
          t.R_W = Quat(X.linear());
          t.orientation_weight = options_.foot_weight;
        }
        // A robot whose legs cannot hold both soles' full pose while the pelvis moves (H1: no ankle
        // roll) lets the feet give way instead; such a shift is halved until the soles stay put,
        // or dropped.
        IkComTarget com_target;
        com_target.weight = options_.com_weight;
        const Vec3 shift_W = target - Vec3(com(0, f), com(1, f), target.z());
        bool held = false;
        for (int attempt = 0; attempt < 3 && !held; ++attempt) {
          const double scale = 1.0 / (1 << attempt);
          com_target.p_W = target - (1 - scale) * shift_W;
          q = integrate(model, q_frame, scale * correction, 1.0);
          ik.solve(data, feet, q_frame, q, com_target);
          update_kinematics(model, data, q);
          held = true;
          for (int foot = 0; foot < 2 && held; ++foot) {
            const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
            const Iso3& X = soles[static_cast<std::size_t>(f)][static_cast<std::size_t>(foot)];
            const Iso3 X_link = link_pose(model, data, sole.link);
            const double moved = (X_link * sole.p_L_center - X.translation()).norm();
            const double turned =
                AngleAxis(X.linear().transpose() * X_link.linear() * R_L_sole[static_cast<std::size_t>(foot)]).angle();
            held = moved <= options_.foot_tolerance_m && turned <= options_.foot_tolerance_rad;
          }
        }
        // The exported re-planned COM is the one the motion follows.
        if (held) {
          ++adjusted;
          clip.com_replanned_W.col(f).head<2>() = com_target.p_W.head<2>();
        } else {
          q = q_frame;
          shift = false;
          ++dropped;
          clip.com_replanned_W.col(f).head<2>() = com.col(f).head<2>();
        }
      }
      bool limited = false;
      if (f > 0) {
        for (int i = 0; i < model.nu(); ++i) {
          if (!(v_max[i] > 0)) continue;
          const double prev = motion.q(7 + i, f - 1);
          const double step = std::max((1 - options_.velocity_margin) * v_max[i] / fps,
                                       std::abs(q_original(7 + i, f) - q_original(7 + i, f - 1)));
          const double clamped = std::clamp(q[7 + i], prev - step, prev + step);
          limited = limited || clamped != q[7 + i];
          q[7 + i] = clamped;
        }
      }
      rate_limited += limited;
      if (!shift && !limited) {
        correction.setZero();
        continue;
      }
      correction = difference(model, q_frame, q, 1.0);
      motion.q.col(f) = q;
      if (shift || limited) {
        update_kinematics(model, data, q);
        max_residual = std::max(max_residual, (com_position(model, data) - clip.com_replanned_W.col(f)).head<2>().norm());
      }
    }
  }

  std::string times;
  for (std::size_t i = 0; i < plan.events.size() && i < 8; ++i)
    times += format("%s%.2f", i ? " " : "", plan.events[i].first);
  if (plan.events.size() > 8) times += " ...";
  ctx.statistics.set("activations", static_cast<double>(plan.events.size()), "", times.empty() ? "" : "first at t = " + times + " s");
  ctx.statistics.set("max-com-shift", max_shift, "m", "planned, after clipping to max_shift");
  ctx.statistics.set("max-planned-shift", max_planned_shift, "m", "as planned, before clipping");
  ctx.statistics.set("clipped-frames", clipped, "frames", "frames whose planned COM shift exceeded max_shift");
  ctx.statistics.set("com-following-residual", max_residual, "m", "max |COM - re-planned COM| after the COM-following IK");
  ctx.statistics.set("adjusted-frames", adjusted, "frames");
  ctx.statistics.set("dropped-frames", dropped, "frames", "shift not followed: the soles would have moved");
  ctx.statistics.set("rate-limited-frames", rate_limited, "frames", "joint steps held to the velocity limits");
}

}  // namespace rt
