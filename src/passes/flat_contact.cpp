#include "retarget/passes/flat_contact.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/quality.hpp"

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
  table_.add("regularization", options_.regularization, "pull towards the original joint angles");
  table_.add("max_iterations", options_.max_iterations, "IK iterations", {0, 10000, ""});
  table_.add("max_offset", options_.max_offset_rad, "[rad] largest offset added to any joint");
  table_.add("max_error_growth", options_.max_error_growth, "largest relative growth of the mean landmark error");
}

namespace {

// Mean per-frame landmark error over (a sample of) the clip with `offset` added to every joint.
double mean_landmark_error(const RobotModel& model, RobotData& data, const Clip& clip, const VecX& offset) {
  const int T = clip.motion.num_frames();
  const int stride = std::max(1, T / 400);
  double sum = 0;
  int n = 0;
  VecX q;
  for (int f = 0; f < T; f += stride) {
    q = clip.motion.q.col(f);
    for (int i = 0; i < model.nu(); ++i) q[7 + i] = std::clamp(q[7 + i] + offset[i], model.q_lower()[i], model.q_upper()[i]);
    const double e = frame_landmark_error_m(model, data, clip.targets, q, f);
    if (std::isfinite(e)) {
      sum += e;
      ++n;
    }
  }
  return n ? sum / n : 0.0;
}

}  // namespace

void FlatContactPass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  RobotMotion& motion = clip.motion;
  const FlatContactOptions& op = options_;
  const std::string where = clip.human.source.path.empty() ? clip.name : clip.human.source.path;
  if (motion.num_frames() == 0) throw InputError("--passes", "flat-contact needs the robot motion of the ik pass: put ik before it");
  require_input(op.max_offset_rad >= 0 && op.max_error_growth >= 0 && op.sole_weight > 0 && op.max_iterations >= 1,
                "flat-contact", "options need max_offset >= 0, max_error_growth >= 0, sole_weight > 0, max_iterations >= 1");
  const int T = motion.num_frames(), nu = model.nu();
  // The paper's frame: both feet down.
  int f0 = 0;
  if (!clip.contacts.empty()) {
    f0 = -1;
    for (int f = 0; f < T && f0 < 0; ++f)
      if (clip.contacts.in_contact[0][static_cast<std::size_t>(f)] && clip.contacts.in_contact[1][static_cast<std::size_t>(f)]) f0 = f;
  }
  if (f0 < 0) {
    ctx.diagnostics.warn(where, "flat-contact: no frame has both feet labelled on the floor; skipped");
    ctx.statistics.set("skipped", 1, "", "no frame with both feet down");
    return;
  }
  IkOptions o;
  o.max_iterations = op.max_iterations;
  o.regularization = op.regularization;
  o.step_tolerance = 1e-7;
  o.cost_tolerance = 1e-9;
  o.root_free = {false, false, true, false, false, false};  // only the root height may follow the feet
  const LandmarkIk ik(model, o);

  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  const VecX q0 = motion.q.col(f0);
  update_kinematics(model, data, q0);
  std::vector<IkTarget> targets;
  double tilt_before = 0;
  for (int foot = 0; foot < 2; ++foot) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
    const Iso3 X = link_pose(model, data, sole.link);
    const Mat3 R_lm = X.linear() * ik.landmark_frame_in_link(sole.link);
    const Vec3 heading = R_lm.col(0);
    IkTarget t;
    t.link = sole.link;
    t.p_L = sole.p_L_center;
    t.p_W = X * sole.p_L_center;
    t.p_W.z() = 0;
    t.weight = op.sole_weight;
    t.R_L_frame = ik.landmark_frame_in_link(sole.link);
    t.R_W = Quat(AngleAxis(std::atan2(heading.y(), heading.x()), Vec3::UnitZ()));
    t.orientation_weight = op.sole_weight;
    targets.push_back(t);
    tilt_before = std::max(tilt_before, sole_tilt_and_height(model, data, q0, foot, R_L_sole[static_cast<std::size_t>(foot)]).first);
    update_kinematics(model, data, q0);
  }
  VecX q_flat = q0;
  const IkResult r = ik.solve(data, targets, q0, q_flat);

  VecX offset = q_flat.tail(nu) - q0.tail(nu);
  int bounded = 0;
  for (int i = 0; i < nu; ++i) {
    const double c = std::clamp(offset[i], -op.max_offset_rad, op.max_offset_rad);
    bounded += c != offset[i];
    offset[i] = c;
  }
  // Never at the clip's expense: halve the offsets while the landmark error grows too much.
  const double error_before = clip.targets[Landmark::Pelvis].present ? mean_landmark_error(model, data, clip, VecX::Zero(nu)) : 0;
  double scale = 1, error_after = error_before;
  if (clip.targets[Landmark::Pelvis].present) {
    for (; scale >= 0.25; scale *= 0.5) {
      error_after = mean_landmark_error(model, data, clip, scale * offset);
      if (error_after <= (1 + op.max_error_growth) * error_before) break;
    }
    if (scale < 0.25) {
      scale = 0;
      error_after = error_before;
      ctx.diagnostics.warn(where, format("flat-contact: the frame-%d offsets would make the landmark error worse by more than "
                                         "%.0f%%; not applied",
                                         f0, 100 * op.max_error_growth));
    }
  }
  clip.flat_contact_offset = scale * offset;
  int clamped = 0;
  for (int f = 0; f < T; ++f) {
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
    tilt_after = std::max(tilt_after, sole_tilt_and_height(model, data, motion.q.col(f0), foot, R_L_sole[static_cast<std::size_t>(foot)]).first);
  ctx.statistics.set("frame", f0, "", "first frame with both feet down");
  ctx.statistics.set("sole-tilt-before", tilt_before * 180 / M_PI, "deg", "worst foot");
  ctx.statistics.set("sole-tilt-after", tilt_after * 180 / M_PI, "deg");
  ctx.statistics.set("max-joint-offset", clip.flat_contact_offset.size() ? clip.flat_contact_offset.cwiseAbs().maxCoeff() : 0.0, "rad");
  ctx.statistics.set("bounded-joints", bounded, "", "offsets cut to max_offset");
  ctx.statistics.set("offset-scale", scale, "", "1: as solved; < 1: reduced to keep the landmark error");
  ctx.statistics.set("landmark-error-before", error_before, "m", "mean over the clip");
  ctx.statistics.set("landmark-error-after", error_after, "m");
  ctx.statistics.set("sole-residual", r.max_error_m, "m");
  ctx.statistics.set("clamped-samples", clamped, "", "frames x joints pushed back inside the limits");
}

}  // namespace rt
