#include "retarget/reference/synthetic_references.hpp"

#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt {

namespace {
double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (10 - 15 * x + 6 * x * x);
}
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

}  // namespace rt
