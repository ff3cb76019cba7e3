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

/// A straight walk (issue 15's synthetic walk): stand, `steps` steps of `step_s` each (double support
/// then single support), the last one bringing the feet side by side, stand again. The COM is a
/// whole-walk ZMP plan (zmp_plan.hpp) whose ZMP stays inside the stance soles shrunk by
/// `zmp_margin_m`, so the reference is dynamically feasible by construction (up to the legs'
/// angular momentum); the joints come from IK with the soles on their footsteps, the swing foot on
/// a smooth arc, the COM on the plan at the standing height, and the trunk upright.
struct WalkOptions {
  int steps = 6;
  double step_length_m = 0.15;   ///< [m] advance of the swing foot past the other foot
  double step_s = 0.5;           ///< [s] one step: double support, then single support
  double double_support_s = 0.1; ///< [s]
  double swing_height_m = 0.04;  ///< [m] sole lift at mid-swing
  double stand_s = 1.0;          ///< [s] standing before the first and after the last step
  double zmp_margin_m = 0.02;    ///< [m]
  /// [m] the COM is held this much below its standing height: long steps need the knees bent
  /// further than the standing pose's to reach both footsteps.
  double com_drop_m = 0.0;
  double fps = 100.0;
  int first_foot = 1;            ///< 0 left, 1 right steps first
  /// The IK pulls every joint towards the standing pose (the waist and arms 100x more firmly than
  /// the legs), and a multibody-correction round that misses the targets more is dropped. Off: the
  /// pull is towards the previous frame, under which the waist and arms drift (by 2.7 rad on G1
  /// over 8 slow steps) and the feet miss their footsteps by 1-3 cm.
  bool hold_standing_pose = true;
};
/// How closely a synthetic walk meets what was asked. Where the legs cannot reach both footsteps
/// at the asked COM height, the IK trades the feet, the COM and the standing pose of the waist and
/// arms off against each other, and the walk is not the one asked for.
struct WalkReport {
  double max_foot_miss_m = 0;     ///< [m] largest distance of a sole centre from its footstep or swing path
  double max_com_miss_m = 0;      ///< [m] largest distance of the COM from the plan at the asked height
  double max_upper_body_rad = 0;  ///< [rad] largest departure of a waist or arm joint from the standing pose
};
Reference walk_reference(const RobotModel& model, const WalkOptions& options = {}, WalkReport* report = nullptr);

}  // namespace rt
