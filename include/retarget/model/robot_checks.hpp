#pragma once
/// Sanity checks of a loaded robot, for `retarget inspect` and `retarget init-robot`: what makes
/// retargeting silently bad rather than failing (a robot facing backwards, swapped feet, a tilted
/// sole, placeholder limits). Each finding is a warning naming the robot.yaml key to look at.

#include "retarget/core/diagnostics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

struct RobotCheckOptions {
  /// [m] a sole centre this far behind its foot link's origin (the ankle) means the toes point
  /// to -X: the robot faces backwards (every shipped robot has it 3-5 cm in front).
  double toes_behind_ankle_m = 0.01;
  double max_sole_tilt_rad = 0.0523598775598;  ///< 3 deg between a sole normal and vertical
  double max_sole_height_m = 0.005;            ///< [m] highest sole corner above the floor
  double placeholder_velocity_rad_s = 50;      ///< velocity limits at or above this look made up
  double min_mass_kg = 2, max_mass_kg = 400;   ///< a humanoid outside this is a unit error
  /// [m] radius of gyration sqrt(I_max / m) of a link above this (or below min, for links over
  /// 50 g) means an inertia in the wrong units or a placeholder.
  double max_gyration_radius_m = 1.0, min_gyration_radius_m = 0.001;
};

/// Runs the checks at the standing pose. Never throws for a loadable model.
Diagnostics check_robot(const RobotModel& model, const RobotCheckOptions& options = {});

}  // namespace rt
