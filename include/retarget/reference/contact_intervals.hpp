#pragma once
/// Conversion between a per-frame contact flag sequence (Reference::contact) and its compact
/// form, the list of stance intervals [begin, end) in frames that meta.json stores.

#include <cstdint>
#include <vector>

namespace rt {

/// Frames [begin, end) of one stance phase (begin < end).
struct FrameInterval {
  int begin = 0;
  int end = 0;
  bool operator==(const FrameInterval& o) const { return begin == o.begin && end == o.end; }
};

/// Maximal runs of non-zero flags, in increasing order; adjacent runs never touch.
std::vector<FrameInterval> contact_intervals(const std::vector<std::uint8_t>& in_contact);

/// Inverse of contact_intervals: `num_frames` flags, 1 inside an interval. The intervals must be
/// ordered, non-overlapping and inside [0, num_frames) (readers check this before calling;
/// InternalError otherwise).
std::vector<std::uint8_t> contact_flags(const std::vector<FrameInterval>& intervals, int num_frames);

}  // namespace rt
