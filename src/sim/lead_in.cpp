#include "retarget/sim/lead_in.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/smoothstep.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/joint_groups.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt {

LeadIn standing_lead_in(const RobotModel& model, const Reference& ref, const LeadInOptions& o) {
  RT_DEMAND(o.max_root_accel_mps2 > 0 && o.max_corner_miss_m >= 0, "standing_lead_in: bad options");
  LeadIn out;
  out.reference = ref;
  if (!ref.has_contacts() || ref.num_frames() < 2 || !(o.lift_s > 0)) return out;
  const bool left = ref.contact[0][0] != 0, right = ref.contact[1][0] != 0;
  if (left == right) return out;
  const int foot = left ? 1 : 0;  // the airborne one
  const ReferenceRobotMap map(model, ref, "reference");
  const VecX q0 = map.q(ref, 0);
  RobotData data(model);
  update_kinematics(model, data, q0);
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  update_kinematics(model, data, q0);

  // Both soles as IK targets: the stance one where it is, the airborne one flat on the floor below
  // its frame-0 pose. The legs move first with the root fixed; where they cannot reach (a trailing
  // leg at its toe-off, stretched), the root may also lower.
  std::vector<IkTarget> targets(2);
  std::array<Iso3, 2> X_target;
  for (int f = 0; f < 2; ++f) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
    Iso3 X = sole_frame_W(model, data, f, R_L_sole[static_cast<std::size_t>(f)]);
    if (f == foot) {
      out.foot_height_m = lowest_sole_corner_z(model, data, f) - lowest_sole_corner_z(model, data, 1 - f);
      X = flat_on_floor(X);
      // The floor is where the stance foot's lowest corner is.
      X.translation().z() = lowest_sole_corner_z(model, data, 1 - f);
    }
    X_target[static_cast<std::size_t>(f)] = X;
    IkTarget& t = targets[static_cast<std::size_t>(f)];
    t.link = sole.link;
    t.p_L = sole.p_L_center;
    t.p_W = X.translation();
    t.weight = 1e4;
    t.R_L_frame = R_L_sole[static_cast<std::size_t>(f)];
    t.R_W = Quat(X.linear());
    t.orientation_weight = 1e3;
  }
  // How far the soles' corners end up from their targets' corners.
  const auto corner_miss = [&](const VecX& q) {
    update_kinematics(model, data, q);
    double worst = 0;
    for (std::size_t f = 0; f < 2; ++f) {
      const Sole& sole = model.soles()[f];
      const auto got = sole_corners_W(sole_frame_W(model, data, static_cast<int>(f), R_L_sole[f]), sole);
      const auto want = sole_corners_W(X_target[f], sole);
      for (std::size_t c = 0; c < 4; ++c) worst = std::max(worst, (got[c] - want[c]).norm());
    }
    return worst;
  };
  IkOptions io;
  io.root_free = {false, false, false, false, false, false};
  io.max_iterations = 100;
  io.step_tolerance = 1e-9;
  io.cost_tolerance = 1e-12;
  io.regularization = 1e-6;
  VecX q_down = q0;
  LandmarkIk(model, io).solve(data, targets, q0, q_down);
  double miss = corner_miss(q_down);
  if (miss > o.max_corner_miss_m) {
    io.root_free[2] = true;
    // The legs start a tenth of the way to the middle of their joints' ranges: a straight stance
    // knee is where the root's height does not change with the knee to first order, and the
    // solver would not leave it.
    VecX q_start = q0;
    const std::vector<JointGroup> groups = joint_groups(model);
    for (int i = 0; i < model.nu(); ++i)
      if (groups[static_cast<std::size_t>(i)] == JointGroup::Legs && std::isfinite(model.q_lower()[i]) &&
          std::isfinite(model.q_upper()[i]))
        q_start[7 + i] += 0.1 * (0.5 * (model.q_lower()[i] + model.q_upper()[i]) - q0[7 + i]);
    VecX q_lowered = q_start;
    LandmarkIk(model, io).solve(data, targets, q_start, q_lowered);
    const double miss_lowered = corner_miss(q_lowered);
    if (miss_lowered < miss) {
      q_down = q_lowered;
      miss = miss_lowered;
    }
  }
  if (miss > o.max_corner_miss_m) {
    // Standing on that foot would be a pose the reference does not have (a sole in the floor or
    // tilted on its edge): no lead-in, the clip starts on its one foot.
    out.skipped = format("the legs cannot put the %s foot down flat below frame 0 (a sole corner stays %.0f mm off)",
                         foot == 0 ? "left" : "right", miss * 1e3);
    return out;
  }
  out.root_drop_m = q0[2] - q_down[2];

  const double fps = ref.fps;
  // [frames] the nominal lead-in (`lift_s`)
  const int n_nominal = std::max(2, static_cast<int>(std::lround(o.lift_s * fps)));
  const double down = 0.4 * n_nominal;  // [frames] held down, then lifted over `lift` frames
  // A smoothstep over a duration D peaks at 6 h / D² for a rise of h.
  const double lift = std::max(0.6 * n_nominal, std::sqrt(6 * std::abs(out.root_drop_m) / o.max_root_accel_mps2) * fps);
  const int n = std::max(n_nominal, static_cast<int>(std::ceil(down + lift)));
  const int T = ref.num_frames();
  Reference& r = out.reference;
  r.root_pos_W.resize(3, n + T);
  r.root_pos_W.rightCols(T) = ref.root_pos_W;
  r.root_quat_W.assign(static_cast<std::size_t>(n), ref.root_quat_W.front());
  r.root_quat_W.insert(r.root_quat_W.end(), ref.root_quat_W.begin(), ref.root_quat_W.end());
  r.joint_pos.resize(ref.joint_pos.rows(), n + T);
  r.joint_pos.rightCols(T) = ref.joint_pos;
  for (int k = 0; k < n; ++k) {
    // Down first (the foot is on the floor while the weight leaves it), then lifted.
    const double s = smoothstep((k - down) / lift);
    r.root_pos_W.col(k) = (1 - s) * q_down.head<3>() + s * q0.head<3>();
    for (int i = 0; i < model.nu(); ++i)
      r.joint_pos(map.column_of_movable(i), k) = (1 - s) * q_down[7 + i] + s * q0[7 + i];
  }
  for (int f = 0; f < 2; ++f) {
    std::vector<std::uint8_t>& c = r.contact[static_cast<std::size_t>(f)];
    std::vector<std::uint8_t> lead(static_cast<std::size_t>(n), 1);
    if (f == foot)
      for (int k = static_cast<int>(std::ceil(down)); k < n; ++k) lead[static_cast<std::size_t>(k)] = 0;
    c.insert(c.begin(), lead.begin(), lead.end());
  }
  // A planned COM/COP of the file no longer matches the frames: dropped (the check plans its own).
  r.com_W.resize(3, 0);
  r.cop_W.resize(2, 0);
  out.frames = n;
  out.duration_s = n / fps;
  out.foot = foot;
  return out;
}

}  // namespace rt
