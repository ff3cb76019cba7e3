#pragma once
/// Standing lead-in of the walking controller's check (issue 15): a clip that starts mid-step (one
/// foot in the air at frame 0) cannot be held still on one foot with its COM between the feet, so
/// the check starts it from a standing pose instead: frame 0 with the airborne foot put down flat
/// on the floor below where it is (leg IK, the rest of the body unchanged), held while the robot
/// settles and shifts its weight, then lifted into frame 0 over `lift_s`. The frames are prepended
/// to the reference; times in the result stay clip times (the lead-in runs before t = 0).

#include <string>

#include "retarget/reference/reference.hpp"

namespace rt {

class RobotModel;

struct LeadIn {
  Reference reference;   ///< the reference with the lead-in frames first (or unchanged)
  int frames = 0;        ///< frames added before the clip's frame 0
  double duration_s = 0; ///< their duration (frames / fps)
  int foot = -1;         ///< the foot put down (0 left, 1 right), −1 when none was needed
  double foot_height_m = 0;  ///< how high that foot was above the floor at frame 0
};

/// The lead-in for `reference` (with a contact schedule). None is added when frame 0 has both or
/// no feet down.
LeadIn standing_lead_in(const RobotModel& model, const Reference& reference, double lift_s = 0.3);

}  // namespace rt
