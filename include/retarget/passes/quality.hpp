#pragma once
/// Quality metrics of a converted clip, with the definitions of design.md §6 (the same numbers go to
/// the summary, meta.json, tests and benchmarks).
///
/// Where they are measured. Landmark errors and jitter on the final robot motion at the source rate
/// (where the scaled landmark targets and the per-frame IK result live). Limits on the source rate
/// too: the exported frames interpolate between source frames, so no exported position or finite-
/// difference speed can exceed the source rate's. Everything about feet and the floor — stance
/// drift, yaw, tilt and height, swing clearance, the lowest point of the robot — on the exported
/// frames (the reference, with its own contact labels), which are what a user or a referee sees;
/// on the source-rate motion when the pipeline has no resample pass.

#include <string>
#include <vector>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/pipeline/clip.hpp"

namespace rt {

class RobotModel;
class RobotData;

/// Landmark error of one landmark over the clip [m].
struct LandmarkErrorStat {
  std::string landmark;
  double median_m = 0;
  double p95_m = 0;
};

struct QualityMetrics {
  /// Per frame: mean distance [m] between the scaled human landmarks and the robot link points they
  /// map to (landmarks with a valid sample and weight > 0); median and p95 over frames.
  double landmark_error_median_m = 0;
  double landmark_error_p95_m = 0;
  std::string worst_landmark;  ///< landmark with the largest mean distance over the clip
  std::vector<LandmarkErrorStat> landmark_errors;  ///< per landmark, in landmark order
  /// Horizontal travel [m] of a sole point from where its labelled stance phase began, over all
  /// stance frames of both feet: p95 and max, at the sole centre and at the heel (the middle of the
  /// sole's rear edge, which shows a pivot about the centre).
  double foot_skating_p95_m = 0;
  double foot_skating_max_m = 0;
  double heel_skating_p95_m = 0;
  double heel_skating_max_m = 0;
  /// The stance phase with the largest centre travel: foot (0 left, 1 right, -1 none) and start [s].
  int worst_stance_foot = -1;
  double worst_stance_start_s = 0;
  /// Within a labelled stance phase: largest turn of the sole about the vertical from the phase's
  /// first frame [deg], largest sole tilt from horizontal [deg], largest |sole-centre height| [m].
  double stance_yaw_drift_max_deg = 0;
  double stance_tilt_max_deg = 0;
  double stance_height_max_m = 0;
  /// Lowest sole corner below the floor [m] over all frames (0 when never below).
  double penetration_max_m = 0;
  /// Lowest point of any collision geometry of any link over all frames [m] (negative: below the
  /// floor), the link and the time [s].
  double lowest_point_m = 0;
  std::string lowest_link;
  double lowest_time_s = 0;
  /// Swing feet: the lowest sole corner [m] over swing frames more than swing_guard_s (0.1 s) from
  /// the swing's lift-off and touchdown, and how many such frames are below 1.5 cm.
  double swing_clearance_min_m = 0;
  int swing_frames_low = 0;
  /// Frames with no foot labelled in stance (flight), and the longest such run [s].
  int frames_without_stance = 0;
  double longest_flight_s = 0;
  /// Frames x joints outside the position limits (must be 0) / above the URDF velocity limits
  /// (finite differences at the source rate), and the worst velocity ratio |q̇| / limit.
  int position_limit_violations = 0;
  int velocity_limit_violations = 0;
  double max_velocity_ratio = 0;
  /// Fastest joint: name and its largest finite-difference speed [rad/s or m/s].
  std::string fastest_joint;
  double fastest_joint_speed = 0;
  /// RMS of the third finite difference of the joint angles [rad/s³]: final motion and the
  /// per-frame IK result it started from.
  double jitter_rad_s3 = 0;
  double jitter_per_frame_ik_rad_s3 = 0;
  /// Frame 0: worst sole tilt [deg] and worst sole-centre height above/below the floor [m] of the
  /// feet labelled in contact there (all feet when there are no labels).
  double frame0_sole_tilt_deg = 0;
  double frame0_sole_height_m = 0;
  /// Multibody ZMP (model/centroidal.hpp: finite differences of the exported frames, URDF masses
  /// and inertias) against the support polygon of the soles labelled in contact on the frame (hull
  /// of their sole rectangles where the feet are), over stance frames other than the clip's first
  /// and last: fraction of frames with the ZMP inside, and within kZmpNear_m of it; the same over
  /// single-support frames; the largest distance outside [m] and its time [s]. Fractions are 1 when
  /// there are no such frames (no labels).
  int zmp_stance_frames = 0;
  int zmp_single_support_frames = 0;
  double zmp_inside_fraction = 1;
  double zmp_near_fraction = 1;
  double zmp_single_inside_fraction = 1;
  double zmp_single_near_fraction = 1;
  double zmp_outside_max_m = 0;
  double zmp_outside_time_s = 0;
  /// Torque demand of the joints with no foot below them (model/torque_demand.hpp: inverse dynamics
  /// of the exported frames, first and last left out): the largest |τ| / effort limit, its joint and
  /// time [s], and the frames where some such joint is above its limit (0 and "" when the robot
  /// gives no effort limits there).
  double torque_demand_max_ratio = 0;
  std::string torque_demand_joint;
  double torque_demand_time_s = 0;
  int torque_demand_frames_over = 0;
};

/// "Near the support" for the ZMP metric [m].
constexpr double kZmpNear_m = 0.01;

/// The ZMP metric's distance of frame f's multibody ZMP outside `support` [m] (negative inside). A
/// frame the floor cannot hold (the body falls faster than (1 − kZmpMinSupport_g) g) has no ZMP:
/// it counts as outside, by the clamped ZMP's distance and at least 2 kZmpNear_m.
double zmp_distance_outside(const SupportPolygon& support, const MultibodyZmp& zmp, int f);

/// Swing frames this close to a lift-off or touchdown [s] are exempt from the clearance metric.
constexpr double kSwingGuard_s = 0.1;
/// Clearance a swing foot keeps outside those frames [m].
constexpr double kSwingClearance_m = 0.015;

QualityMetrics compute_quality(const RobotModel& model, RobotData& data, const Clip& clip);

/// The foot and floor metrics (skating, stance yaw/tilt/height, penetration, lowest point, swing
/// clearance, frames without stance, frame-0 flatness, ZMP) of a motion `q` (nq x T) at `fps` with its
/// contact labels (may be empty); the other fields of the result stay 0. stance_only: for a caller
/// that needs the stance metrics alone, the costly parts they do not need are skipped (the lowest
/// point of the collision geometry and the ZMP; those fields keep their defaults).
QualityMetrics foot_metrics(const RobotModel& model, RobotData& data, const MatX& q, double fps,
                            const std::array<std::vector<std::uint8_t>, 2>& contacts, bool stance_only = false);

/// The ZMP fields of QualityMetrics for a motion `q` (nq x T) at `fps` with its contact labels
/// (written into `m`; nothing when the labels are empty). Updates `data`.
void add_zmp_metrics(const RobotModel& model, RobotData& data, const MatX& q, double fps,
                     const std::array<std::vector<std::uint8_t>, 2>& contacts, QualityMetrics& m);

/// Landmark error of one frame [m]: the mean distance between the scaled landmark targets valid at
/// `frame` and the robot points they map to at configuration `q` (the per-frame value of
/// landmark_error_*; NaN when no landmark is valid there). Updates `data`. When `per_landmark` is
/// given, each distance is also appended to its landmark's list.
double frame_landmark_error_m(const RobotModel& model, RobotData& data, const LandmarkTargets& targets, const VecXCRef& q,
                              int frame, std::array<std::vector<double>, kLandmarkCount>* per_landmark = nullptr);

/// RMS third finite difference of joint angles (rows 7.. of q) [rad/s³].
double joint_jitter(const MatX& q, double fps);

}  // namespace rt
