#pragma once
/// Standing lead-in of the walking controller's check (issue 15): a clip that starts mid-step (one
/// foot in the air at frame 0) cannot be held still on one foot with its COM between the feet, so
/// the check starts it from a standing pose instead: frame 0 with the airborne foot put down flat
/// on the floor below where it is (leg IK; where the legs cannot reach, the root lowers too, and
/// nothing else changes), held while the robot settles and shifts its weight, then lifted into
/// frame 0 (LeadInOptions). The frames are prepended to the reference; times in the result stay
/// clip times (the lead-in runs before t = 0).

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
  double root_drop_m = 0;    ///< how far the root was lowered to put it down (0: the legs reached)
  std::string skipped;       ///< why no lead-in was added to a clip that starts on one foot (else empty)
};

struct LeadInOptions {
  /// [s] the put-down pose is held for 40 % of this (the weight leaves the foot), and the foot is
  /// lifted into frame 0 over the rest
  double lift_s = 0.3;
  /// [m] the foot is down when every corner of both soles is this close to where it should be
  double max_corner_miss_m = 0.002;
  /// [m/s²] a lowered root rises back into frame 0 no faster than this (a smoothstep's peak), so
  /// the lift takes longer where the root was lowered far: the balance plan follows the reference's
  /// vertical acceleration, and the lowered roots of the shared gaits (up to 7.7 cm) would rise at
  /// up to 14 m/s² over 0.18 s, a motion the clip does not ask for.
  double max_root_accel_mps2 = 2.0;
};

/// The lead-in for `reference` (with a contact schedule). None is added when frame 0 has both or
/// no feet down, nor when the legs cannot put the foot down: some corner of either sole would stay
/// more than `max_corner_miss_m` from where it should be (`skipped` says so).
LeadIn standing_lead_in(const RobotModel& model, const Reference& reference, const LeadInOptions& options = {});

}  // namespace rt
