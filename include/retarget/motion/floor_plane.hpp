#pragma once
/// The floor under a motion as a plane, estimated from where the feet stand (design.md §3.1): the
/// samples of each foot landmark (ankle, toe, heel) that barely move horizontally are contact
/// candidates; their heights are fitted by least squares with a plane z = a·x + b·y plus one height
/// per landmark (an ankle rests higher than a toe), trimmed from above (a foot held still in the
/// air is an outlier, a foot on the floor is not). The slope is only fitted along horizontal directions the
/// candidates span (>= min_spread_m); a standing clip gets a level floor.

#include "retarget/motion/human_motion.hpp"

namespace rt {

struct FloorPlaneOptions {
  double still_speed_legs_per_s = 0.3;  ///< [leg lengths / s] candidates move slower than this (source time)
  double min_spread_m = 0.5;            ///< [m] fit a slope only along directions the candidates span this far (1σ)
  double max_tilt_deg = 10;             ///< steeper fits are not a floor: keep the level plane (and say so)
};

struct FloorPlane {
  double a = 0, b = 0, c = 0;  ///< z = a x + b y + c [m]: the plane through the lowest landmark's contacts
  double tilt_deg = 0;         ///< angle of the plane's normal from vertical
  /// Spread of the candidate heights about the plane (p90 − p10 of the kept candidates) [m]:
  /// a floor that is not a plane (steps, drift) shows here.
  double unevenness_m = 0;
  int candidates = 0;          ///< contact samples used
  bool rejected_steep = false; ///< a fit steeper than max_tilt_deg was discarded
  double height_at(double x, double y) const { return a * x + b * y + c; }
};

/// Leg length of the subject [m]: median hip-knee plus knee-ankle over both legs, or 0 when the
/// landmarks are missing.
double human_leg_length(const HumanMotion& motion);

FloorPlane estimate_floor_plane(const HumanMotion& motion, const FloorPlaneOptions& options = {});

/// Removes the plane's slope: subtracts a·x + b·y from every landmark height (a small shear: the
/// tilts this is used for are a few degrees). The floor height itself is left to the caller.
void level_onto_floor(HumanMotion& motion, const FloorPlane& plane);

}  // namespace rt
