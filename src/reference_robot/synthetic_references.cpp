#include "retarget/reference/synthetic_references.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/balance/zmp_plan.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/smoothstep.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt {

namespace {
// How much more firmly the synthetic walk holds the waist and arms at the standing pose than the legs
// (both far below the weights of the feet and the COM).
constexpr double kUpperBodyHold = 100;
// [m] a foot or COM target met to within this counts as met.
constexpr double kTargetTolerance_m = 0.002;
}  // namespace

Reference foot_lift_reference(const RobotModel& model, const FootLiftOptions& o) {
  if (!(o.lift_start_s >= 0 && o.lift_end_s > o.lift_start_s + 2 * o.ramp_s && o.duration_s >= o.lift_end_s))
    throw InputError("foot-lift reference: need 0 <= start < start + 2 ramp < end <= duration");
  const VecX q0 = model.standing_q();
  Reference ref = constant_reference(model, q0, o.duration_s, o.fps);
  RobotData data(model);
  IkOptions io;
  io.root_free = {false, false, false, false, false, false};
  io.max_iterations = 100;
  io.step_tolerance = 1e-8;
  io.cost_tolerance = 1e-10;
  io.regularization = 1e-4;
  const LandmarkIk ik(model, io);
  update_kinematics(model, data, q0);
  std::vector<IkTarget> targets(2);
  for (int foot = 0; foot < 2; ++foot) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
    const Iso3 X = link_pose(model, data, sole.link);
    IkTarget& t = targets[static_cast<std::size_t>(foot)];
    t.link = sole.link;
    t.p_L = sole.p_L_center;
    t.p_W = X * sole.p_L_center;
    t.weight = 100;
    t.R_L_frame = Mat3::Identity();
    t.R_W = Quat(X.linear());
    t.orientation_weight = 100;
  }
  const Vec3 p_lift0 = targets[static_cast<std::size_t>(o.foot)].p_W;
  VecX q = q0;
  for (int f = 0; f < ref.num_frames(); ++f) {
    const double t = f / o.fps;
    const double s = smoothstep((t - o.lift_start_s) / o.ramp_s) * (1 - smoothstep((t - (o.lift_end_s - o.ramp_s)) / o.ramp_s));
    targets[static_cast<std::size_t>(o.foot)].p_W = p_lift0 + Vec3(0, 0, o.height_m * s);
    const VecX q_prev = q;
    ik.solve(data, targets, q_prev, q);
    for (std::size_t c = 0; c < ref.joint_names.size(); ++c)
      ref.joint_pos(static_cast<Eigen::Index>(c), f) = q[7 + model.export_joint_order()[c]];
    ref.contact[static_cast<std::size_t>(o.foot)][static_cast<std::size_t>(f)] = (t >= o.lift_start_s && t < o.lift_end_s) ? 0 : 1;
  }
  return ref;
}

Reference walk_reference(const RobotModel& model, const WalkOptions& o, WalkReport* report) {
  if (!(o.steps >= 1 && o.steps <= 100 && o.step_s > o.double_support_s && o.double_support_s >= 0 && o.stand_s >= 0 &&
        o.fps > 0 && std::abs(o.step_length_m) <= 1 && o.swing_height_m >= 0 && (o.first_foot == 0 || o.first_foot == 1)))
    throw InputError("walk reference: need 1-100 steps, step_s > double_support_s >= 0, stand_s >= 0, fps > 0, |step| <= 1 m");
  const VecX q0 = model.standing_q();
  const double duration = 2 * o.stand_s + o.steps * o.step_s + o.double_support_s;
  Reference ref = constant_reference(model, q0, duration, o.fps);
  const int T = ref.num_frames();
  RobotData data(model);
  update_kinematics(model, data, q0);
  const Vec3 com0 = com_position(model, data);

  // Footsteps: sole poses of each foot per step (flat, standing heading), and the swing timing.
  std::array<Iso3, 2> sole0;
  for (int f = 0; f < 2; ++f) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
    const Iso3 X = link_pose(model, data, sole.link);
    sole0[static_cast<std::size_t>(f)] = Iso3::Identity();
    sole0[static_cast<std::size_t>(f)].linear() = X.linear() * sole.R_L_S;  // the sole's axes, not the link's
    sole0[static_cast<std::size_t>(f)].translation() = X * sole.p_L_center;
  }
  struct Step {
    int foot;
    double t_lift, t_land;
    Vec3 from, to;
  };
  std::vector<Step> plan_steps;
  std::array<double, 2> x{{0, 0}};
  for (int i = 0; i < o.steps; ++i) {
    const int foot = (o.first_foot + i) % 2;
    const int other = 1 - foot;
    const double t0 = o.stand_s + i * o.step_s + o.double_support_s;
    const double target = i + 1 == o.steps ? x[static_cast<std::size_t>(other)] : x[static_cast<std::size_t>(other)] + o.step_length_m;
    const Vec3 base = sole0[static_cast<std::size_t>(foot)].translation();
    plan_steps.push_back({foot, t0, t0 + o.step_s - o.double_support_s, base + Vec3(x[static_cast<std::size_t>(foot)], 0, 0),
                          base + Vec3(target, 0, 0)});
    x[static_cast<std::size_t>(foot)] = target;
  }
  // Sole position of a foot at time t, and whether it is down.
  auto sole_at = [&](int foot, double t, bool& down) {
    Vec3 p = sole0[static_cast<std::size_t>(foot)].translation();
    down = true;
    for (const Step& s : plan_steps) {
      if (s.foot != foot) continue;
      if (t >= s.t_land) {
        p = s.to;
      } else if (t >= s.t_lift) {
        const double tau = (t - s.t_lift) / (s.t_land - s.t_lift);
        p = s.from + smoothstep(tau) * (s.to - s.from);
        p.z() += o.swing_height_m * 0.5 * (1 - std::cos(2 * M_PI * tau));
        down = false;
        break;
      } else {
        break;
      }
    }
    return p;
  };

  // Whole-walk COM plan: the COM pulled towards the support's centre, its ZMP inside the soles.
  const double dt = 0.01;
  const int K = static_cast<int>(std::floor(duration / dt + 1e-9)) + 1;
  std::vector<ZmpPlanSample> samples(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) {
    const double t = k * dt;
    std::vector<Vec2> corners;
    for (int f = 0; f < 2; ++f) {
      bool down = false;
      const Vec3 p = sole_at(f, t, down);
      if (!down) continue;
      const Vec2 half = 0.5 * model.soles()[static_cast<std::size_t>(f)].size_m.head<2>();
      const Mat2 R = sole0[static_cast<std::size_t>(f)].linear().topLeftCorner<2, 2>();
      for (const Vec2& c : {Vec2(1, 1), Vec2(-1, 1), Vec2(-1, -1), Vec2(1, -1)}) corners.push_back(p.head<2>() + R * half.cwiseProduct(c));
    }
    const SupportPolygon polygon = SupportPolygon::convex_hull(std::move(corners));
    ZmpPlanSample& s = samples[static_cast<std::size_t>(k)];
    s.com_ref_W = polygon.centroid();
    s.zmp_gain_s2 = (com0.z() - o.com_drop_m) / 9.81;
    s.support = polygon.half_planes(o.zmp_margin_m);
  }
  ZmpPlanOptions po;
  po.period_s = dt;
  po.jerk_weight = 1e-6;

  IkOptions io;
  io.root_free = {true, true, true, false, false, false};  // the trunk stays upright
  // The feet and the COM leave the waist and arms redundant. Regularised towards the previous frame
  // they drift, frame after frame (a G1 walk of 0.1 m steps ended with the waist at -1.0 rad yaw,
  // +0.52 roll and -0.52 pitch, and fell over it). With hold_standing_pose every joint is pulled
  // towards the standing pose instead, the waist and arms more firmly than the legs.
  std::vector<bool> is_leg(static_cast<std::size_t>(model.nu()), false);
  for (const Sole& sole : model.soles())
    for (const int v : link_dof_chain(model, sole.link))
      if (v >= 6) is_leg[static_cast<std::size_t>(v - 6)] = true;
  if (o.hold_standing_pose) {
    io.regularization_factors = VecX::Ones(model.nv());
    for (int a = 0; a < model.nu(); ++a)
      if (!is_leg[static_cast<std::size_t>(a)]) io.regularization_factors[6 + a] = kUpperBodyHold;
  }
  io.max_iterations = 100;
  io.step_tolerance = 1e-9;
  io.cost_tolerance = 1e-12;
  io.regularization = 1e-5;
  const LandmarkIk ik(model, io);
  std::vector<IkTarget> targets(2);
  for (int f = 0; f < 2; ++f) {
    IkTarget& t = targets[static_cast<std::size_t>(f)];
    const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
    t.link = sole.link;
    t.p_L = sole.p_L_center;
    t.weight = 1e4;
    t.R_L_frame = Mat3::Identity();
    update_kinematics(model, data, q0);
    t.R_W = Quat(link_pose(model, data, sole.link).linear());
    t.orientation_weight = 1e4;
  }
  // The joints for a COM plan; two-stage preview (Kajita et al. 2003): the legs' angular momentum
  // moves the whole-body ZMP off the cart-table one, so the plan is made again with that offset
  // until the motion's own multibody ZMP stays inside the soles.
  // Each realisation says how closely it met its targets: where the legs cannot reach, the IK
  // trades the targets off against each other (and against the standing pose of the upper body).
  MatX q_all(model.nq(), T);
  VecX max_step = VecX::Constant(model.nu(), std::numeric_limits<double>::infinity());
  for (int a = 0; a < model.nu(); ++a)
    if (model.velocity_limits()[a] > 0) max_step[a] = 0.99 * model.velocity_limits()[a] / o.fps;
  IkJointBounds speed_bounds;
  auto realise = [&](const ZmpPlan& plan) {
    WalkReport met;
    VecX q = q0;
    for (int frame = 0; frame < T; ++frame) {
      const double t = frame / o.fps;
      for (int f = 0; f < 2; ++f) {
        bool down = false;
        targets[static_cast<std::size_t>(f)].p_W = sole_at(f, t, down);
        ref.contact[static_cast<std::size_t>(f)][static_cast<std::size_t>(frame)] = down ? 1 : 0;
      }
      const double s = std::clamp(t / dt, 0.0, static_cast<double>(K - 1));
      const int i = std::min(static_cast<int>(s), std::max(K - 2, 0)), j = std::min(i + 1, K - 1);
      IkComTarget com;
      com.p_W << (1 - (s - i)) * plan.com_W.col(i) + (s - i) * plan.com_W.col(j), com0.z() - o.com_drop_m;
      com.weight = 1e4;
      com.horizontal_only = false;
      VecX anchor = q;  // the previous frame; or the standing joints, the root where the previous frame left it
      if (o.hold_standing_pose) anchor.tail(model.nu()) = q0.tail(model.nu());
      // Every joint within its URDF velocity limit from the previous frame (with 1 % to spare for
      // the file's rounding): a reference that asks a motor for more fails the check.
      if (frame > 0) {
        speed_bounds.lower = q.tail(model.nu()) - max_step;
        speed_bounds.upper = q.tail(model.nu()) + max_step;
      }
      const IkResult r = ik.solve(data, targets, anchor, q, com, IkFloorTerm{}, frame > 0 ? &speed_bounds : nullptr);
      met.max_foot_miss_m = std::max(met.max_foot_miss_m, r.max_error_m);
      met.max_com_miss_m = std::max(met.max_com_miss_m, (com_position(model, data) - com.p_W).norm());
      for (int a = 0; a < model.nu(); ++a)
        if (!is_leg[static_cast<std::size_t>(a)])
          met.max_upper_body_rad = std::max(met.max_upper_body_rad, std::abs(q[7 + a] - q0[7 + a]));
      q_all.col(frame) = q;
    }
    return met;
  };
  auto miss = [](const WalkReport& m) { return std::max(m.max_foot_miss_m, m.max_com_miss_m); };
  ZmpPlan plan = plan_com_zmp(samples, po);
  if (plan.com_W.cols() != K) throw InternalError("walk reference: the COM plan failed");
  WalkReport met = realise(plan);
  // With hold_standing_pose a correction round is kept only while the motion still meets its
  // targets: the multibody ZMP of a motion that misses them is not the plan's, and correcting by it
  // feeds the miss back (an 8-step humanoid25 walk went from a 7 mm miss to 0.8 m in one round).
  for (int round = 0; round < 3; ++round) {
    const MultibodyZmp mb = multibody_zmp(model, data, q_all, o.fps);
    for (int k = 0; k < K; ++k) {
      const int frame = std::clamp(static_cast<int>(std::lround(k * dt * o.fps)), 1, std::max(T - 2, 1));
      const Vec2 acc = (mb.com_W.col(frame + 1) - 2 * mb.com_W.col(frame) + mb.com_W.col(frame - 1)).head<2>() * o.fps * o.fps;
      const Vec2 cart = mb.com_W.col(frame).head<2>() - mb.zmp_gain_s2[frame] * acc;
      samples[static_cast<std::size_t>(k)].zmp_offset_W = mb.zmp_W.col(frame) - cart;
    }
    const ZmpPlan corrected = plan_com_zmp(samples, po);
    if (corrected.com_W.cols() != K) throw InternalError("walk reference: the COM plan failed");
    const MatX q_kept = q_all;
    const WalkReport corrected_met = realise(corrected);
    if (o.hold_standing_pose && miss(corrected_met) > std::max(miss(met), kTargetTolerance_m)) {
      q_all = q_kept;
      break;
    }
    met = corrected_met;
  }
  if (report) *report = met;
  for (int frame = 0; frame < T; ++frame) {
    const VecX& q = q_all.col(frame);
    ref.root_pos_W.col(frame) = q.head<3>();
    ref.root_quat_W[static_cast<std::size_t>(frame)] = model.root_link_orientation(Quat(q[3], q[4], q[5], q[6]).normalized());
    for (std::size_t c = 0; c < ref.joint_names.size(); ++c)
      ref.joint_pos(static_cast<Eigen::Index>(c), frame) = q[7 + model.export_joint_order()[c]];
  }
  return ref;
}

}  // namespace rt
