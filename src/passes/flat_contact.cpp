#include "retarget/passes/flat_contact.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

std::pair<double, double> sole_tilt_and_height(const RobotModel& model, RobotData& data, const VecX& q, int foot,
                                               const Mat3& R_L_sole) {
  update_kinematics(model, data, q);
  const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
  const Iso3 X = link_pose(model, data, sole.link);
  const Vec3 n = X.linear() * R_L_sole.col(2);
  const double tilt = std::acos(std::clamp(n.z(), -1.0, 1.0));
  return {tilt, (X * sole.p_L_center).z()};
}

FlatContactPass::FlatContactPass() {
  table_.add("sole_weight", options_.sole_weight, "weight of the flat sole targets");
  table_.add("regularization", options_.regularization, "pull towards the original frame-0 joint angles");
  table_.add("max_iterations", options_.max_iterations, "IK iterations");
}

void FlatContactPass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  RobotMotion& motion = clip.motion;
  if (motion.num_frames() == 0) throw InternalError("flat-contact: run the ik pass first");
  IkOptions o;
  o.max_iterations = options_.max_iterations;
  o.regularization = options_.regularization;
  o.step_tolerance = 1e-7;
  o.cost_tolerance = 1e-9;
  o.root_free = {false, false, true, false, false, false};  // only the root height may follow the feet
  const LandmarkIk ik(model, o);

  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  const VecX q0 = motion.q.col(0);
  update_kinematics(model, data, q0);
  std::vector<IkTarget> targets;
  double tilt_before = 0;
  for (int foot = 0; foot < 2; ++foot) {
    const bool in_contact = clip.contacts.empty() || clip.contacts.in_contact[static_cast<std::size_t>(foot)][0];
    if (!in_contact) continue;
    const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
    const Iso3 X = link_pose(model, data, sole.link);
    const Mat3 R_lm = X.linear() * ik.landmark_frame_in_link(sole.link);
    const Vec3 heading = R_lm.col(0);
    IkTarget t;
    t.link = sole.link;
    t.p_L = sole.p_L_center;
    t.p_W = X * sole.p_L_center;
    t.p_W.z() = 0;
    t.weight = options_.sole_weight;
    t.R_L_frame = ik.landmark_frame_in_link(sole.link);
    t.R_W = Quat(AngleAxis(std::atan2(heading.y(), heading.x()), Vec3::UnitZ()));
    t.orientation_weight = options_.sole_weight;
    targets.push_back(t);
    tilt_before = std::max(tilt_before, sole_tilt_and_height(model, data, q0, foot, R_L_sole[static_cast<std::size_t>(foot)]).first);
    update_kinematics(model, data, q0);
  }
  if (targets.empty()) {
    ctx.diagnostics.warn(clip.human.source.path, "flat-contact: no foot in contact at frame 0; nothing to flatten");
    return;
  }
  VecX q_flat = q0;
  const IkResult r = ik.solve(data, targets, q0, q_flat);

  const int nu = model.nu();
  clip.flat_contact_offset = q_flat.tail(nu) - q0.tail(nu);
  int clamped = 0;
  for (int f = 0; f < motion.num_frames(); ++f) {
    for (int i = 0; i < nu; ++i) {
      double& v = motion.q(7 + i, f);
      v += clip.flat_contact_offset[i];
      const double c = std::clamp(v, model.q_lower()[i], model.q_upper()[i]);
      clamped += c != v;
      v = c;
    }
  }
  double tilt_after = 0;
  for (int foot = 0; foot < 2; ++foot)
    tilt_after = std::max(tilt_after, sole_tilt_and_height(model, data, motion.q.col(0), foot, R_L_sole[static_cast<std::size_t>(foot)]).first);
  ctx.statistics.set("sole-tilt-before", tilt_before * 180 / M_PI, "deg", "frame 0, worst foot");
  ctx.statistics.set("sole-tilt-after", tilt_after * 180 / M_PI, "deg");
  ctx.statistics.set("max-joint-offset", clip.flat_contact_offset.cwiseAbs().maxCoeff(), "rad");
  ctx.statistics.set("sole-residual", r.max_error_m, "m");
  ctx.statistics.set("clamped-samples", clamped, "", "frames x joints pushed back inside the limits");
}

}  // namespace rt
