#pragma once
/// Gap handling for landmark tracks from marker data: interior gaps up to a length limit are
/// interpolated, longer ones (and those at the ends) stay Missing and hold the nearest valid
/// sample, as HumanMotion documents; and the leading/trailing frames where the subject is not
/// (fully) in view are found so that they can be trimmed.

#include <string>
#include <vector>

#include "retarget/motion/human_motion.hpp"

namespace rt {

/// A run of missing frames [begin, end) of one track.
struct FrameGap {
  int begin = 0;
  int end = 0;
  int length() const { return end - begin; }
};

/// Result of fill_gaps for one track.
struct GapReport {
  int filled_gaps = 0;            ///< interior gaps interpolated
  int filled_frames = 0;
  std::vector<FrameGap> long_gaps;  ///< interior gaps left Missing (longer than the limit)
  FrameGap leading;               ///< missing frames before the first valid one (length 0 if none)
  FrameGap trailing;              ///< missing frames after the last valid one
  bool has_valid = false;         ///< the track has at least one valid frame
};

/// Fills interior gaps of at most `max_gap_frames` frames by cubic Hermite interpolation between
/// the samples around the gap (tangents from the neighbouring samples where they are valid,
/// otherwise the chord), marking them SampleState::Interpolated. Longer gaps and the ends stay
/// Missing and take the nearest valid sample's position. A track without a valid frame is left
/// as it is.
GapReport fill_gaps(LandmarkTrack& track, int max_gap_frames);

/// The span [begin, end) outside which at least one of the `needed` landmarks is not yet or no
/// longer in view: begin = the latest first-valid frame over `needed`, end = the earliest
/// last-valid frame + 1. Absent landmarks are ignored; begin >= end when the needed landmarks are
/// never in view within a common span. Interior gaps do not shorten the span.
FrameGap common_valid_span(const HumanMotion& motion, const std::vector<Landmark>& needed);

/// Keeps frames [begin, end) of every landmark track (positions, states, orientations) and
/// updates num_frames.
void trim_frames(HumanMotion& motion, int begin, int end);

}  // namespace rt
