#include "retarget/sim/lead_in.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/smoothstep.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/foot_down.hpp"
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
  const FootDown down_pose = put_foot_down(model, data, q0, foot, R_L_sole, o.max_corner_miss_m);
  out.foot_height_m = down_pose.foot_height_m;
  const VecX& q_down = down_pose.q;
  const double miss = down_pose.corner_miss_m;
  if (!down_pose.reached) {
    // Standing on that foot would be a pose the reference does not have (a sole in the floor or
    // tilted on its edge): no lead-in, the clip starts on its one foot.
    out.skipped = format("the legs cannot put the %s foot down flat below frame 0 (a sole corner stays %.0f mm off)",
                         foot == 0 ? "left" : "right", miss * 1e3);
    return out;
  }
  out.root_drop_m = down_pose.root_drop_m;

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
