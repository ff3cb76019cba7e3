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

/// Frames that repeat the previous one (within noise): the signature of data up-sampled by
/// repetition and stored with a higher rate than it was captured at.
struct RepeatedFrames {
  int repeated = 0;       ///< frames equal (within the tolerance below) to the previous one
  int run_length = 0;     ///< the common length of the runs of repeats (1: every other frame), 0 = no pattern
  double data_fps = 0;    ///< [Hz] the rate the data then has: fps / (run_length + 1), rounded to a whole Hz within 0.1 %; 0 = no pattern
};

/// Looks for a regular pattern of repeated frames. A frame repeats when no landmark moved more
/// than 1e-6 m, or 5 % of the clip's 75th-percentile frame-to-frame displacement up to 0.5 mm
/// (noise), on the landmarks measured in both frames (at least half the present ones; gap-filled
/// samples are no evidence). A pattern: at least 30 % of the frames repeat, and at least 80 % of
/// the runs of repeats have one length of at most 4 and are separated by one moving frame. A clip
/// holding still (one long run, or noise-length runs at random) is not such a pattern.
RepeatedFrames find_repeated_frames(const HumanMotion& motion);

/// [g] A body's centre of mass cannot fall faster than gravity (the floor only pushes). The mean of
/// the landmarks stands in for it, smoothed over kCentreSmoothing_s; on the shared real clips it
/// falls at up to 1.4 g (jumps, dance), so a fall beyond kMaxCentreFall_g for kMinCentreFall_s
/// means the clip plays faster than it was captured: a time scale s multiplies accelerations by s².
inline constexpr double kMaxCentreFall_g = 2.0;
inline constexpr double kCentreSmoothing_s = 0.05;  ///< [s] Gaussian sigma, source time
inline constexpr double kMinCentreFall_s = 0.05;    ///< [s] source time

struct CentreFall {
  double peak_g = 0;       ///< [g] the fastest downward acceleration of the landmarks' mean (positive)
  double span_s = 0;       ///< [s] the longest span beyond kMaxCentreFall_g
  int slow_down = 0;       ///< the smallest integer time scale that brings peak_g to 1 g; 0 = plausible
  double data_fps = 0;     ///< [Hz] fps / slow_down (rounded as RepeatedFrames::data_fps): the highest plausible rate; 0 = plausible
};

/// The landmarks' mean over the frames where every present landmark is valid (gaps split the
/// clip), measured on the source timeline (fps · time_scale).
CentreFall find_centre_fall(const HumanMotion& motion);

/// Warnings "frame rate N Hz contradicted by the data: ...; pass --source-fps M if so" for repeated
/// frames and a centre falling faster than gravity, added to motion.diagnostics (load_motion runs
/// it unless --source-fps was given). Without either, a clip of the cgspeed CMU conversions
/// (profiles cmu_* but cmu_asf) stating 120 Hz gets a note that some CMU subjects were captured at
/// 60 Hz: such a clip at twice its speed is still plausible human motion (the salsa of subjects
/// 60/61 in the shared data falls at most at 0.96 g at its stated 120 Hz), so the data cannot tell.
void check_frame_rate_against_data(HumanMotion& motion);

}  // namespace rt
