#pragma once
/// Plausibility checks of a loaded clip that catch wrong units and wrong frame rates before they
/// turn into a silently wrong reference (load_motion runs them on every source).

#include <optional>

#include "retarget/motion/human_motion.hpp"

namespace rt {

/// A stature outside this range [m] after unit detection means the units are wrong (a cm clip
/// read as metres gives ~160 m, a metre clip read as cm 1.6 cm).
inline constexpr double kMinPlausibleStature_m = 0.5;
inline constexpr double kMaxPlausibleStature_m = 2.5;

/// [m] The subject's stature: the reader's estimate (source.details "stature_m", BVH) or else the
/// head landmark's height above the floor at its first measured sample divided by 0.87 (head
/// centre / stature); nullopt when there is neither.
std::optional<double> estimate_stature_m(const HumanMotion& motion);

/// Throws InputError "<file>: implausible stature ..." when the estimate is outside
/// [kMinPlausibleStature_m, kMaxPlausibleStature_m], naming the units and whether they were
/// detected or given, and --source-units / --force.
void check_stature(const HumanMotion& motion);

/// Frames that repeat the previous one exactly: the signature of data up-sampled by repetition
/// and stored with a higher rate than it was captured at.
struct RepeatedFrames {
  int repeated = 0;       ///< frames equal (within 1e-6 m on every landmark) to the previous one
  int run_length = 0;     ///< the common length of the runs of repeats (1: every other frame), 0 = no pattern
  double data_fps = 0;    ///< [Hz] the rate the data then has: fps / (run_length + 1); 0 = no pattern
};

/// Looks for a regular pattern of repeated frames: at least 30 % of the frames repeats, and at
/// least 80 % of the runs of repeats of one length of at most 4. A clip holding still (one long
/// run) is not such a pattern.
RepeatedFrames find_repeated_frames(const HumanMotion& motion);

}  // namespace rt
