#pragma once
/// A leg's two ends, from the kinematic tree: the hip is the child link of the leg's movable joint
/// nearest the root (its origin is that joint's, and it moves with the root), the ankle that of
/// the movable joint nearest the sole (fixed in the sole's frame). The distance between their
/// origins at the neutral pose (q = 0) is taken as the leg's length: the leg is straight there on
/// G1, humanoid25 and JVRC-1, nearly so on H1 (its walks reach 1.035 of it).

#include <array>

namespace rt {

class RobotModel;

class RobotData;

struct LegEnds {
  int hip_link = -1;    ///< -1: the sole's link has no movable joint above it
  int ankle_link = -1;
  double length_m = 0;  ///< [m] hip-ankle distance at the neutral pose (0 without two joints)
};

/// Left and right (the model's soles).
std::array<LegEnds, 2> leg_ends(const RobotModel& model);

/// [m] hip-ankle distance of `leg` at the pose `data` holds (update_kinematics first).
double hip_ankle_distance_m(const RobotModel& model, const RobotData& data, const LegEnds& leg);

}  // namespace rt
