#pragma once
/// Joint groups of a humanoid from its kinematic tree (robot.yaml `controller.group_gains`, the
/// check's per-group tracking errors): a leg joint moves a sole; an arm joint moves a hand (or
/// wrist, elbow) landmark's link but not the head, neck or chest landmark's (so the waist is torso);
/// every other movable joint is torso. Robots without arm landmarks have no arm joints.

#include <string>
#include <vector>

namespace rt {

class RobotModel;

enum class JointGroup { Legs, Torso, Arms };

/// "legs", "torso", "arms".
const char* joint_group_name(JointGroup group);

/// The group of every movable joint (model order, nu entries).
std::vector<JointGroup> joint_groups(const RobotModel& model);

}  // namespace rt
