#pragma once
/// A one-footed pose with its airborne foot put down: the other sole flat on the floor below where
/// it is (the floor being the stance sole's lowest corner), the stance sole where it is, by leg IK.
/// Where the legs cannot reach with the root fixed (a stretched trailing leg at its toe-off), the
/// root may also lower. Used to start or end a clip that starts or ends on one foot standing on
/// both: the check's standing lead-in (sim/lead_in.hpp) and com-plan's lead-in and lead-out.

#include <array>

#include "retarget/core/types.hpp"
#include "retarget/ik/landmark_ik.hpp"

namespace rt {

class RobotModel;
class RobotData;

/// The IK target holding sole `foot` at the sole frame X_W_sole (position weight 1e4, orientation
/// 1e3). `R_L_sole` is that sole's frame in its link.
IkTarget sole_pose_target(const RobotModel& model, int foot, const Iso3& X_W_sole, const Mat3& R_L_sole);

/// [m] The largest distance of a corner of sole `foot` (at the kinematics in `data`) from the same
/// corner at the sole frame X_W_sole.
double sole_corner_miss(const RobotModel& model, const RobotData& data, int foot, const Mat3& R_L_sole, const Iso3& X_W_sole);

/// Options of those sole-placing solves: converged to micrometres, the root fixed but for its
/// height where `root_height_free`.
IkOptions sole_ik_options(bool root_height_free);

struct FootDown {
  VecX q;                    ///< the pose with both feet down (valid when `reached`)
  bool reached = false;      ///< every corner of both soles within `max_corner_miss_m` of its target
  double corner_miss_m = 0;  ///< the largest distance of a sole corner from its target
  double root_drop_m = 0;    ///< how far the root was lowered (0: the legs reached with it fixed)
  double foot_height_m = 0;  ///< how high the airborne foot's lowest corner was above the stance one's
};

/// Puts `foot` (0 left, 1 right) of pose `q0` down. `R_L_sole` are the sole frames in their links
/// (sole_frames_in_links). Uses `data` as scratch.
FootDown put_foot_down(const RobotModel& model, RobotData& data, const VecX& q0, int foot,
                       const std::array<Mat3, 2>& R_L_sole, double max_corner_miss_m);

}  // namespace rt
