#include "retarget/reference/contact_intervals.hpp"

#include "retarget/core/error.hpp"

namespace rt {

std::vector<FrameInterval> contact_intervals(const std::vector<std::uint8_t>& in_contact) {
  std::vector<FrameInterval> out;
  const int n = static_cast<int>(in_contact.size());
  for (int t = 0; t < n;) {
    if (!in_contact[static_cast<std::size_t>(t)]) {
      ++t;
      continue;
    }
    FrameInterval iv;
    iv.begin = t;
    while (t < n && in_contact[static_cast<std::size_t>(t)]) ++t;
    iv.end = t;
    out.push_back(iv);
  }
  return out;
}

std::vector<std::uint8_t> contact_flags(const std::vector<FrameInterval>& intervals, int num_frames) {
  std::vector<std::uint8_t> flags(static_cast<std::size_t>(num_frames), 0);
  int previous_end = 0;
  for (const FrameInterval& iv : intervals) {
    RT_DEMAND(iv.begin >= previous_end && iv.begin < iv.end && iv.end <= num_frames,
              "contact intervals must be ordered, non-empty and inside the clip");
    for (int t = iv.begin; t < iv.end; ++t) flags[static_cast<std::size_t>(t)] = 1;
    previous_end = iv.end;
  }
  return flags;
}

}  // namespace rt
