#pragma once
/// Quality metrics of a converted clip, with the definitions of design.md §6 (the same numbers go to
/// the summary, meta.json, tests and benchmarks). Computed on the final robot motion at the source
/// rate (after every pass, before resampling).

#include <string>

#include "retarget/pipeline/clip.hpp"

namespace rt {

class RobotModel;
class RobotData;

struct QualityMetrics {
  /// Per frame: mean distance [m] between the scaled human landmarks and the robot link points they
  /// map to (landmarks with a valid sample and weight > 0); median and p95 over frames.
  double landmark_error_median_m = 0;
  double landmark_error_p95_m = 0;
  std::string worst_landmark;  ///< landmark with the largest mean distance over the clip
  /// Horizontal travel [m] of a sole centre from where its labelled stance phase began, over all
  /// stance frames of both feet: p95 (and max).
  double foot_skating_p95_m = 0;
  double foot_skating_max_m = 0;
  /// Lowest sole corner below the floor [m] over all frames (0 when never below).
  double penetration_max_m = 0;
  /// Frames x joints outside the position limits (must be 0) / above the URDF velocity limits
  /// (finite differences at the source rate), and the worst velocity ratio |q̇| / limit.
  int position_limit_violations = 0;
  int velocity_limit_violations = 0;
  double max_velocity_ratio = 0;
  /// RMS of the third finite difference of the joint angles [rad/s³]: final motion and the
  /// per-frame IK result it started from.
  double jitter_rad_s3 = 0;
  double jitter_per_frame_ik_rad_s3 = 0;
  /// Frame 0: worst sole tilt [deg] and worst sole-centre height above/below the floor [m].
  double frame0_sole_tilt_deg = 0;
  double frame0_sole_height_m = 0;
};

QualityMetrics compute_quality(const RobotModel& model, RobotData& data, const Clip& clip);

/// RMS third finite difference of joint angles (rows 7.. of q) [rad/s³].
double joint_jitter(const MatX& q, double fps);

}  // namespace rt
