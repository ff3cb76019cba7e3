#pragma once
/// A leg's two ends, from the kinematic tree: the hip is the child link of the leg's movable joint
/// nearest the root (its origin is that joint's, and it moves with the root), the ankle that of
/// the movable joint nearest the sole (fixed in the sole's frame). The distance between their
/// origins is the leg's reach: straight at the neutral pose on every robot here.

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
