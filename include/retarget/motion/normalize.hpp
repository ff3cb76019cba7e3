#pragma once
/// Steps shared by every motion source after its own reader has produced landmark positions in
/// metres with Z up (design.md §3.1): floor estimation, start alignment and anatomical frames.

#include "retarget/motion/human_motion.hpp"

namespace rt {

struct NormalizeOptions {
  /// Rotate about Z and translate horizontally so the pelvis starts above the origin facing +X.
  bool align_start = true;
  /// Move the estimated floor to z = 0.
  bool move_floor_to_zero = true;
  /// Percentile (0..1) of the per-frame lowest foot landmark height taken as the floor; a low
  /// percentile ignores a few glitched frames but still finds the floor in clips with jumps.
  double floor_percentile = 0.02;
  /// Fit a plane to the feet's contacts (floor_plane.hpp) and level the motion onto it when it is
  /// tilted more than level_min_tilt_deg; warn above warn_tilt_deg, or when the contacts spread more
  /// than warn_unevenness_m about the plane.
  bool level_floor = true;
  double level_min_tilt_deg = 0.2;
  double warn_tilt_deg = 1.0;
  double warn_unevenness_m = 0.03;
};

/// Rotation that maps a source frame with the given up axis ('x', 'y', 'z'; `negative` for a
/// downward-pointing axis) to Z up, keeping the frame right-handed.
Mat3 up_axis_to_z_up(char up_axis, bool negative = false);

/// Height [m] of the floor under the feet: the `percentile` of the lowest foot landmark
/// (ankle, toe, heel) per frame over all frames with a valid foot landmark. Throws InputError when
/// the motion has no foot landmarks.
double estimate_floor_height(const HumanMotion& motion, double percentile);

/// Rigid transform applied by `align_start`: after it the pelvis is at (0, 0, z) at frame 0 and the
/// subject faces +X (left hip to the +Y side). Identity when the hips or shoulders are missing.
Iso3 start_alignment(const HumanMotion& motion);

/// Applies `X_new_old` to every landmark position (and orientation, if any).
void transform_motion(HumanMotion& motion, const Iso3& X_new_old);

/// Derives anatomical orientations from positions (design convention in LandmarkTrack): pelvis
/// (hips + spine/chest), chest (shoulders + neck/pelvis), feet (ankle, toe, heel). Landmarks whose
/// inputs are missing keep has_orientation = false.
void derive_orientations(HumanMotion& motion);

/// Runs floor estimation (records source.floor_height_m), floor shift, alignment, floor levelling
/// (source.floor_tilt_deg) and orientation derivation, in that order. Readers call this last.
void normalize_motion(HumanMotion& motion, const NormalizeOptions& options = {});

}  // namespace rt
