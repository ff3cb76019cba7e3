#include "retarget/passes/com_replan.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/flat_contact.hpp"

namespace rt {

ComReplanPlan plan_com(const BalanceController& balance, const ComReplanOptions& o, const Eigen::Matrix2Xd& com_W,
                       const std::function<const SupportFrame&(int)>& support) {
  const int K = static_cast<int>(com_W.cols());
  RT_DEMAND(K > 0, "plan_com: empty COM trajectory");
  const int N = o.horizon;
  const ClosedLoopModel model = balance.closed_loop_model(o.period_s);
  const ComReplanner planner(model, o);
  ComReplanPlan plan;
  plan.period_s = o.period_s;
  plan.com_original_W = com_W;
  // The working reference, padded with its last value so every window holds N steps.
  Eigen::Matrix2Xd U(2, K + N);
  U.leftCols(K) = com_W;
  for (int k = K; k < K + N; ++k) U.col(k) = com_W.col(K - 1);
  plan.cop_predicted_W.resize(2, K);
  plan.com_predicted_W.resize(2, K);
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

ComReplanPass::ComReplanPass() {
  table_.add("horizon", options_.replan.horizon, "N: prediction window in model steps");
  table_.add("period", options_.replan.period_s, "[s] discretisation of the balance model (eq. 25)");
  table_.add("h_max", options_.replan.h_max, "eq. 33/34: how close to the polygon border the desired COP may be");
  table_.add("w", options_.replan.w, "eq. 31: W_ii = w i^2");
  table_.add("margin", options_.replan.margin_m, "[m] the predicted COP must stay this far inside the polygon");
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
  if (T == 0) throw InternalError("com-replan: run the ik pass first");
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
  const ComReplanPlan plan = plan_com(balance, options_.replan, com_grid, [&](int k) -> const SupportFrame& {
    return support[static_cast<std::size_t>(frame_at(k * dt))];
  });

  // Back to source frames.
  auto grid_at = [&](const Eigen::Matrix2Xd& g, double t) -> Vec2 {
    const double s = std::clamp(t / dt, 0.0, static_cast<double>(K - 1));
    const int i = std::min(static_cast<int>(s), K - 1), j = std::min(i + 1, K - 1);
    return (1 - (s - i)) * g.col(i) + (s - i) * g.col(j);
  };
  clip.com_replanned_W.resize(3, T);
  clip.cop_predicted_W.resize(2, T);
  double max_shift = 0;
  for (int f = 0; f < T; ++f) {
    const Vec2 c = grid_at(plan.com_predicted_W, f / fps);
    clip.com_replanned_W.col(f) << c, com(2, f);
    clip.cop_predicted_W.col(f) = grid_at(plan.cop_predicted_W, f / fps);
    max_shift = std::max(max_shift, (c - com.col(f).head<2>()).norm());
  }

  // COM-following IK: feet held where they are, COM pulled onto the re-planned COM. Frames whose COM
  // barely moves are left alone; the others start from the previous frame's correction, which is
  // nearly the answer (the correction varies slowly), so a few iterations suffice.
  double max_residual = 0;
  int adjusted = 0;
  if (!plan.events.empty()) {
    IkOptions o;
    o.max_iterations = options_.ik_iterations;
    o.regularization = options_.posture_regularization;
    o.step_tolerance = 1e-5;
    o.cost_tolerance = 1e-4;
    const LandmarkIk ik(model, o);
    VecX correction = VecX::Zero(model.nv());  // last frame's q_solved ⊖ q_frame
    std::vector<IkTarget> feet(2);
    for (int f = 0; f < T; ++f) {
      const VecX q_frame = motion.q.col(f);
      const Vec3 target = clip.com_replanned_W.col(f);
      if ((target - com.col(f)).head<2>().norm() < options_.min_shift_m) {
        correction.setZero();
        continue;
      }
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
      IkComTarget com_target;
      com_target.p_W = target;
      com_target.weight = options_.com_weight;
      VecX q = integrate(model, q_frame, correction, 1.0);
      ik.solve(data, feet, q_frame, q, com_target);
      correction = difference(model, q_frame, q, 1.0);
      motion.q.col(f) = q;
      ++adjusted;
      update_kinematics(model, data, q);
      max_residual = std::max(max_residual, (com_position(model, data) - target).head<2>().norm());
    }
  }

  std::string times;
  for (std::size_t i = 0; i < plan.events.size() && i < 8; ++i)
    times += format("%s%.2f", i ? " " : "", plan.events[i].first);
  if (plan.events.size() > 8) times += " ...";
  ctx.statistics.set("activations", static_cast<double>(plan.events.size()), "", times.empty() ? "" : "first at t = " + times + " s");
  ctx.statistics.set("max-com-shift", max_shift, "m");
  ctx.statistics.set("com-following-residual", max_residual, "m", "max |COM - re-planned COM| after the COM-following IK");
  ctx.statistics.set("adjusted-frames", adjusted, "frames");
}

}  // namespace rt
