#include "retarget/model/leg_ends.hpp"

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

double hip_ankle_distance_m(const RobotModel& model, const RobotData& data, const LegEnds& leg) {
  return (link_pose(model, data, leg.hip_link).translation() - link_pose(model, data, leg.ankle_link).translation()).norm();
}

std::array<LegEnds, 2> leg_ends(const RobotModel& model) {
  std::array<LegEnds, 2> legs;
  for (std::size_t k = 0; k < 2; ++k)
    for (int l = model.soles()[k].link; l >= 0 && model.links()[static_cast<std::size_t>(l)].parent_joint >= 0;) {
      const Joint& j = model.joints()[static_cast<std::size_t>(model.links()[static_cast<std::size_t>(l)].parent_joint)];
      if (j.qpos_index >= 0 && j.type != JointType::Floating) {
        if (legs[k].ankle_link < 0) legs[k].ankle_link = j.child_link;
        legs[k].hip_link = j.child_link;
      }
      l = j.parent_link;
    }
  RobotData data(model);
  VecX q_neutral = model.standing_q();
  q_neutral.tail(model.nu()).setZero();
  update_kinematics(model, data, q_neutral);
  for (LegEnds& leg : legs)
    if (leg.hip_link >= 0 && leg.hip_link != leg.ankle_link) leg.length_m = hip_ankle_distance_m(model, data, leg);
  return legs;
}

}  // namespace rt
