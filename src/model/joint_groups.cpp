#include "retarget/model/joint_groups.hpp"

#include <set>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

const char* joint_group_name(JointGroup group) {
  switch (group) {
    case JointGroup::Legs: return "legs";
    case JointGroup::Torso: return "torso";
    case JointGroup::Arms: return "arms";
  }
  return "?";
}

std::vector<JointGroup> joint_groups(const RobotModel& model) {
  // Dofs (v order; the root's six come first) moving each kind of link.
  auto dofs_of = [&](int link, std::set<int>& out) {
    if (link < 0) return;
    for (int d : link_dof_chain(model, link)) out.insert(d);
  };
  std::set<int> legs, arms, upper;
  for (const Sole& s : model.soles()) dofs_of(s.link, legs);
  for (const LandmarkTarget& t : model.config().landmarks) {
    const int link = model.link_index(t.link);
    switch (t.landmark) {
      case Landmark::LeftHand: case Landmark::RightHand: case Landmark::LeftWrist: case Landmark::RightWrist:
      case Landmark::LeftElbow: case Landmark::RightElbow:
        dofs_of(link, arms);
        break;
      case Landmark::Head: case Landmark::Neck: case Landmark::Chest:
        dofs_of(link, upper);
        break;
      default:
        break;
    }
  }
  std::vector<JointGroup> out(static_cast<std::size_t>(model.nu()), JointGroup::Torso);
  for (int i = 0; i < model.nu(); ++i) {
    const int dof = 6 + i;
    if (legs.count(dof)) out[static_cast<std::size_t>(i)] = JointGroup::Legs;
    else if (arms.count(dof) && !upper.count(dof)) out[static_cast<std::size_t>(i)] = JointGroup::Arms;
  }
  return out;
}

}  // namespace rt
