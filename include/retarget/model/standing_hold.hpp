#pragma once
/// A simple standing test of the generated MuJoCo model: hold a pose with a joint-space PD through
/// the torque motors (effort-limited) and watch for a fall. Used by the robot tests (every robot
/// must stand) and the model benchmark; the dynamics check has its own, full controller.

#include <string>

#include "retarget/core/types.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

struct StandingHoldOptions {
  double duration_s = 2.0;  ///< [s] simulated time
  /// Held (and initial) configuration, size nq; empty: model.standing_q(). Starts at rest.
  VecX q_target;
  /// PD gains for every joint; negative: robot.yaml's simulation.hold_kp / hold_kd. Each joint's
  /// gains are capped at half the explicit-Euler stability limit of its own inertia I (diagonal of
  /// the mass matrix, armature included): kp <= I / (2 dt^2), kd <= I / (2 dt).
  double kp = -1;  ///< [N m/rad] (N/m for prismatic joints)
  double kd = -1;  ///< [N m s/rad]
  /// The run stops at the first fall: a non-sole geom touching the floor, the COM below this
  /// fraction of its initial height, or the root tilted more than max_tilt_rad from upright.
  double min_com_height_fraction = 0.5;
  double max_tilt_rad = 0.785398163397448;  ///< 45 deg
};

struct StandingHoldResult {
  bool fell = false;
  std::string failure;      ///< first fall cause ("link 'x' touched the floor at t = 1.23 s"); empty otherwise
  double simulated_s = 0;   ///< [s] simulated time (less than the duration after a fall)
  int steps = 0;            ///< mj_step calls
  double initial_root_height_m = 0, final_root_height_m = 0;
  double min_root_height_m = 0, max_root_height_m = 0;
  double max_tilt_rad = 0;            ///< max angle between the root z axis and world z
  double initial_com_height_m = 0, final_com_height_m = 0;
  double max_com_drift_m = 0;         ///< [m] max horizontal COM travel from its start
  double final_max_joint_error = 0;   ///< [rad] max |q - q_target| over joints at the end
  bool unstable = false;              ///< MuJoCo reported a numerical instability (bad qacc)
};

/// Runs the standing hold on a fresh mjData of `model`. Never prints; no state is shared with
/// other calls (safe to run in parallel threads on one model).
StandingHoldResult simulate_standing_hold(const RobotModel& model, const StandingHoldOptions& options = {});

}  // namespace rt
