#pragma once
/// Can the robot stand on one foot? The COM-over-sole reach of static single support, found by IK
/// from the standing pose: one sole held where it stands (position and orientation), the other
/// lifted off the floor and free to move, the COM pulled horizontally towards the held sole's
/// centre in small steps (a continuation, so the IK follows one branch of poses), within the joint
/// limits. A robot whose COM cannot be brought inside a sole this way cannot hold a foot up without
/// falling, whatever the controller: a foot lift or a slow step asks it for more than its
/// kinematics give (e.g. a wide stance and no ankle roll: the stance leg cannot lean sideways).
///
/// This is kinematics only (no torques); the dynamics check judges the rest.

#include <array>
#include <string>

#include "retarget/core/diagnostics.hpp"
#include "retarget/core/types.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

struct SingleSupportReachOptions {
  double lift_m = 0.05;          ///< [m] the free sole's weak target: this far above where it stands
  double free_sole_weight = 0.01;///< weight of that target (relative to the COM's 1): low, so the leg may swing
  int continuation_steps = 20;   ///< COM target moved from the standing COM to the sole centre in this many steps
  int iterations_per_step = 40;  ///< IK iterations per continuation step
};

struct SingleSupportReach {
  /// [m] horizontal distance of the reached COM from the held sole's rectangle (0 when inside).
  double com_outside_sole_m = 0;
  double com_to_centre_m = 0;           ///< [m] horizontal distance of the reached COM from the sole centre
  double standing_com_to_centre_m = 0;  ///< [m] the same at the standing pose: how far the COM had to move
  Vec3 com_W = Vec3::Zero();            ///< [m] the reached COM (the standing root frame's world)
  VecX q;                               ///< the reached pose (nq)
};

/// Per foot (left, right): that foot held, the other free. Never prints or throws for a loaded model.
std::array<SingleSupportReach, 2> single_support_reach(const RobotModel& model, const SingleSupportReachOptions& options = {});

/// "reached (1.2 cm from its centre)" or "stops 9.1 cm outside it", for a summary line.
std::string describe_reach(const SingleSupportReach& reach, double tolerance_m = 0.005);

/// A warning (at robot.yaml's feet.<side>) for each foot the COM cannot be brought over by more
/// than `tolerance_m`: that robot cannot stand on that foot.
Diagnostics check_single_support(const RobotModel& model, const std::array<SingleSupportReach, 2>& reach,
                                 double tolerance_m = 0.005);

}  // namespace rt
