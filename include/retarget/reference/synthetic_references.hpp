#pragma once
/// Synthetic joint-space references for tests, benchmarks and the paper's experiments, built with
/// the robot's own IK so they work for any robot config.

#include "retarget/model/robot_model.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

/// Paper §VII-A (Fig. 7): stand, lift the right foot during [lift_start_s, lift_end_s) and put it
/// down again, the left foot flat on the floor throughout. The reference does NOT shift the COM
/// towards the stance foot: deciding that is the dynamic mapping's job.
struct FootLiftOptions {
  double duration_s = 3.0;
  double lift_start_s = 1.0;
  double lift_end_s = 2.0;
  double height_m = 0.05;     ///< sole lift
  double ramp_s = 0.25;       ///< raise / lower time inside the lift interval
  double fps = 100.0;
  int foot = 1;               ///< 0 left, 1 right (the paper lifts the right foot)
};

/// The standing pose with one sole raised by IK (root and the other foot fixed), as a reference
/// whose contact schedule marks the lifted foot in swing during the lift interval.
Reference foot_lift_reference(const RobotModel& model, const FootLiftOptions& options = {});

}  // namespace rt
