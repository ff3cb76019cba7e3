#pragma once
/// A leg's two ends, from the kinematic tree: the hip is the child link of the leg's movable joint
/// nearest the root (its origin is that joint's, and it moves with the root), the ankle that of
/// the movable joint nearest the sole (fixed in the sole's frame). The distance between their
/// origins at the neutral pose (q = 0) is taken as the leg's length: the leg is straight there on
/// G1, humanoid25 and JVRC-1, nearly so on H1 (its walks reach 1.035 of it).

#include <array>

namespace rt {

class RobotModel;

struct LegEnds {
  int hip_link = -1;    ///< -1: the sole's link has no movable joint above it
  int ankle_link = -1;
};

/// Left and right (the model's soles).
std::array<LegEnds, 2> leg_ends(const RobotModel& model);

}  // namespace rt
