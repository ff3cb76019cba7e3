#include "retarget/model/leg_ends.hpp"

#include "retarget/model/robot_model.hpp"

namespace rt {

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
  return legs;
}

}  // namespace rt
