#include "retarget/sim/lead_in.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/smoothstep.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt {

LeadIn standing_lead_in(const RobotModel& model, const Reference& ref, double lift_s) {
  LeadIn out;
  out.reference = ref;
  if (!ref.has_contacts() || ref.num_frames() < 2 || !(lift_s > 0)) return out;
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
  // its frame-0 pose, with only the legs free (root fixed).
  std::vector<IkTarget> targets(2);
  for (int f = 0; f < 2; ++f) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
    const Iso3 X_link = link_pose(model, data, sole.link);
    Iso3 X = Iso3::Identity();
    X.linear() = X_link.linear() * R_L_sole[static_cast<std::size_t>(f)];
    X.translation() = X_link * sole.p_L_center;
    if (f == foot) {
      out.foot_height_m = lowest_sole_corner_z(model, data, f) - lowest_sole_corner_z(model, data, 1 - f);
      X = flat_on_floor(X);
      // The floor is where the stance foot's lowest corner is.
      X.translation().z() = lowest_sole_corner_z(model, data, 1 - f);
    }
    IkTarget& t = targets[static_cast<std::size_t>(f)];
    t.link = sole.link;
    t.p_L = sole.p_L_center;
    t.p_W = X.translation();
    t.weight = 1e4;
    t.R_L_frame = R_L_sole[static_cast<std::size_t>(f)];
    t.R_W = Quat(X.linear());
    t.orientation_weight = 1e3;
  }
  IkOptions io;
  io.root_free = {false, false, false, false, false, false};
  io.max_iterations = 100;
  io.step_tolerance = 1e-9;
  io.cost_tolerance = 1e-12;
  io.regularization = 1e-6;
  const LandmarkIk ik(model, io);
  VecX q_down = q0;
  ik.solve(data, targets, q0, q_down);

  const double fps = ref.fps;
  const int n = std::max(2, static_cast<int>(std::lround(lift_s * fps)));
  const int T = ref.num_frames();
  Reference& r = out.reference;
  r.root_pos_W.resize(3, n + T);
  r.root_pos_W << ref.root_pos_W.col(0).replicate(1, n), ref.root_pos_W;
  r.root_quat_W.assign(static_cast<std::size_t>(n), ref.root_quat_W.front());
  r.root_quat_W.insert(r.root_quat_W.end(), ref.root_quat_W.begin(), ref.root_quat_W.end());
  r.joint_pos.resize(ref.joint_pos.rows(), n + T);
  r.joint_pos.rightCols(T) = ref.joint_pos;
  for (int k = 0; k < n; ++k) {
    // Down for the first 40 % (the foot is on the floor while the weight leaves it), then lifted.
    const double s = smoothstep((k - 0.4 * n) / (0.6 * n));
    for (int i = 0; i < model.nu(); ++i)
      r.joint_pos(map.column_of_movable(i), k) = (1 - s) * q_down[7 + i] + s * q0[7 + i];
  }
  for (int f = 0; f < 2; ++f) {
    std::vector<std::uint8_t>& c = r.contact[static_cast<std::size_t>(f)];
    std::vector<std::uint8_t> lead(static_cast<std::size_t>(n), 1);
    if (f == foot)
      for (int k = static_cast<int>(std::ceil(0.4 * n)); k < n; ++k) lead[static_cast<std::size_t>(k)] = 0;
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
