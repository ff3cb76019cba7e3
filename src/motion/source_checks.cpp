#include "retarget/motion/source_checks.hpp"

#include <cmath>
#include <cstdlib>
#include <map>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

constexpr double kHeadCentreStatureRatio = 0.87;  // as the BVH reader's head-joint estimate
constexpr double kRepeatTolerance_m = 1e-6;

}  // namespace

std::optional<double> estimate_stature_m(const HumanMotion& m) {
  if (const auto it = m.source.details.find("stature_m"); it != m.source.details.end()) {
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end != it->second.c_str() && std::isfinite(v)) return v;
  }
  const LandmarkTrack& head = m[Landmark::Head];
  if (!head.present) return std::nullopt;
  for (int t = 0; t < m.num_frames; ++t)
    if (head.state[static_cast<std::size_t>(t)] == SampleState::Measured) return head.p_W(2, t) / kHeadCentreStatureRatio;
  return std::nullopt;
}

void check_stature(const HumanMotion& m) {
  const std::optional<double> stature = estimate_stature_m(m);
  if (!stature || (*stature >= kMinPlausibleStature_m && *stature <= kMaxPlausibleStature_m)) return;
  const MotionSourceInfo& s = m.source;
  throw InputError(s.path, format("implausible stature %.3g m with units %s (%s): a person is %.1f-%.1f m tall, so the "
                                  "units are probably wrong; give the right --source-units (or --force to convert anyway)",
                                  *stature, s.units.c_str(), s.units_overridden ? "from --source-units" : "detected",
                                  kMinPlausibleStature_m, kMaxPlausibleStature_m));
}

RepeatedFrames find_repeated_frames(const HumanMotion& m) {
  RepeatedFrames out;
  std::map<int, int> runs;  // run length -> count
  int run = 0;
  for (int t = 1; t < m.num_frames; ++t) {
    bool same = false;
    for (const LandmarkTrack& l : m.landmarks) {
      if (!l.present) continue;
      if (l.state[static_cast<std::size_t>(t)] != SampleState::Measured ||
          l.state[static_cast<std::size_t>(t - 1)] != SampleState::Measured) {
        same = false;
        break;
      }
      same = (l.p_W.col(t) - l.p_W.col(t - 1)).cwiseAbs().maxCoeff() <= kRepeatTolerance_m;
      if (!same) break;
    }
    if (same) {
      ++out.repeated;
      ++run;
    } else if (run > 0) {
      ++runs[run];
      run = 0;
    }
  }
  if (run > 0) ++runs[run];
  if (m.num_frames < 10 || out.repeated < 0.3 * m.num_frames) return out;
  int total = 0, best = 0, best_count = 0;
  for (const auto& [length, count] : runs) {
    total += count;
    if (count > best_count) best = length, best_count = count;
  }
  if (best <= 4 && best_count >= 0.8 * total) {
    out.run_length = best;
    out.data_fps = m.fps / (best + 1);
  }
  return out;
}

}  // namespace rt
