#include "retarget/motion/source_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

// A suggested rate as a user would type it: 29.9999 Hz (a BVH's rounded frame time) is 30.
double typed_rate(double hz) {
  const double whole = std::round(hz);
  return std::abs(hz - whole) <= 1e-3 * hz ? whole : hz;
}

constexpr double kHeadCentreStatureRatio = 0.87;  // as the BVH reader's head-joint estimate
constexpr double kRepeatTolerance_m = 1e-6;
constexpr double kNoiseFraction = 0.05;  // of the 75th-percentile frame displacement
constexpr double kMaxNoise_m = 5e-4;

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
  const int n = m.num_frames;
  int present = 0;
  for (const LandmarkTrack& l : m.landmarks) present += l.present;
  // Largest landmark displacement into each frame, over the landmarks measured in both frames;
  // < 0 where fewer than half the present landmarks are.
  std::vector<double> moved(static_cast<std::size_t>(std::max(n, 1)), -1.0);
  std::vector<double> moving;
  for (int t = 1; t < n; ++t) {
    double d = 0;
    int compared = 0;
    for (const LandmarkTrack& l : m.landmarks) {
      if (!l.present || l.state[static_cast<std::size_t>(t)] != SampleState::Measured ||
          l.state[static_cast<std::size_t>(t - 1)] != SampleState::Measured)
        continue;
      ++compared;
      d = std::max(d, (l.p_W.col(t) - l.p_W.col(t - 1)).cwiseAbs().maxCoeff());
    }
    if (present > 0 && 2 * compared >= present + 1) {
      moved[static_cast<std::size_t>(t)] = d;
      moving.push_back(d);
    }
  }
  if (moving.empty()) return out;
  const auto q75 = moving.begin() + static_cast<std::ptrdiff_t>(moving.size() * 3 / 4);
  std::nth_element(moving.begin(), q75, moving.end());
  const double tolerance = std::max(kRepeatTolerance_m, std::min(kNoiseFraction * *q75, kMaxNoise_m));

  std::map<int, int> runs;  // run length -> count
  int run = 0, lone_moves = 0, moves = 0, since_move = 0;
  for (int t = 1; t < n; ++t) {
    const double d = moved[static_cast<std::size_t>(t)];
    if (d >= 0 && d <= tolerance) {
      ++out.repeated;
      ++run;
      continue;
    }
    if (run > 0) {
      ++runs[run];
      ++moves;
      lone_moves += since_move == 1;  // the moving stretch before this run was one frame long
      run = 0;
      since_move = 0;
    }
    ++since_move;
  }
  if (run > 0) ++runs[run];
  if (n < 10 || out.repeated < 0.3 * n) return out;
  int total = 0, best = 0, best_count = 0;
  for (const auto& [length, count] : runs) {
    total += count;
    if (count > best_count) best = length, best_count = count;
  }
  // Up-sampling by repetition: runs of one length, each after a single moving frame (noise in a
  // still stretch gives runs and moving stretches of random lengths).
  if (best <= 4 && best_count >= 0.8 * total && lone_moves >= 0.8 * std::max(moves - 1, 1)) {
    out.run_length = best;
    out.data_fps = typed_rate(m.fps / (best + 1));
  }
  return out;
}

CentreFall find_centre_fall(const HumanMotion& m) {
  CentreFall out;
  const int n = m.num_frames;
  const double fps = m.fps * m.time_scale;  // frames per source second
  if (n < 3 || !(fps > 0)) return out;
  std::vector<bool> valid(static_cast<std::size_t>(n), true);
  std::vector<double> z(static_cast<std::size_t>(n), 0.0);
  int present = 0;
  for (const LandmarkTrack& l : m.landmarks) {
    if (!l.present) continue;
    ++present;
    for (int t = 0; t < n; ++t) {
      valid[static_cast<std::size_t>(t)] = valid[static_cast<std::size_t>(t)] && l.valid(t);
      z[static_cast<std::size_t>(t)] += l.p_W(2, t);
    }
  }
  if (present < 3) return out;
  const double sigma = kCentreSmoothing_s * fps;  // [frames]
  const int reach = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> kernel(static_cast<std::size_t>(2 * reach + 1));
  for (int k = -reach; k <= reach; ++k) kernel[static_cast<std::size_t>(k + reach)] = std::exp(-0.5 * k * k / (sigma * sigma));
  const double g = 9.80665;
  const int min_span = std::max(1, static_cast<int>(std::lround(kMinCentreFall_s * fps)));
  double peak = 0;
  int longest = 0;
  for (int a = 0; a < n;) {  // each stretch of frames with every landmark valid
    if (!valid[static_cast<std::size_t>(a)]) {
      ++a;
      continue;
    }
    int b = a;
    while (b < n && valid[static_cast<std::size_t>(b)]) ++b;
    // Smoothed height on [a, b), then the acceleration away from the stretch's ends (where the
    // kernel would be cut).
    std::vector<double> h(static_cast<std::size_t>(b - a));
    for (int t = a; t < b; ++t) {
      double sum = 0, weight = 0;
      for (int k = -reach; k <= reach; ++k) {
        const int u = t + k;
        if (u < a || u >= b) continue;
        sum += kernel[static_cast<std::size_t>(k + reach)] * z[static_cast<std::size_t>(u)];
        weight += kernel[static_cast<std::size_t>(k + reach)];
      }
      h[static_cast<std::size_t>(t - a)] = sum / weight / present;
    }
    int span = 0;
    for (int t = a + reach + 1; t < b - reach - 1; ++t) {
      const std::size_t i = static_cast<std::size_t>(t - a);
      const double acc = (h[i + 1] - 2 * h[i] + h[i - 1]) * fps * fps;  // [m/s^2]
      peak = std::max(peak, -acc / g);
      span = -acc > kMaxCentreFall_g * g ? span + 1 : 0;
      longest = std::max(longest, span);
    }
    a = b;
  }
  out.peak_g = peak;
  out.span_s = longest / fps;
  if (longest >= min_span) {
    out.slow_down = std::max(2, static_cast<int>(std::ceil(std::sqrt(peak) - 1e-9)));
    out.data_fps = typed_rate(m.fps / out.slow_down);
  }
  return out;
}

void check_frame_rate_against_data(HumanMotion& m) {
  const std::string& path = m.source.path;
  const RepeatedFrames r = find_repeated_frames(m);
  if (r.run_length > 0) {
    const std::string pattern = r.run_length == 1 ? std::string("every 2nd frame repeats its predecessor")
                                                   : format("every frame is held for %d frames", r.run_length + 1);
    m.diagnostics.warn(path, format("frame rate %g Hz contradicted by the data: %s (%d of %d frames; likely %g Hz); "
                                    "pass --source-fps %g if so",
                                    m.fps, pattern.c_str(), r.repeated, m.num_frames, r.data_fps, r.data_fps));
    return;
  }
  const CentreFall f = find_centre_fall(m);
  if (f.slow_down > 0) {
    m.diagnostics.warn(path, format("frame rate %g Hz contradicted by the data: the body's centre falls at up to %.1f g "
                                    "(for %.2f s), faster than gravity lets it (likely %g Hz or lower); pass "
                                    "--source-fps %g if so",
                                    m.fps, f.peak_g, f.span_s, f.data_fps, f.data_fps));
    return;
  }
  // What the data cannot show: B. Hahne's cgspeed BVH conversions of the CMU library (our cmu_*
  // skeleton profiles but the ASF one) state 120 Hz for every trial, but a few subjects were
  // captured at 60 Hz; at twice its speed such a clip is still a plausible human motion.
  const std::string& profile = m.source.profile;
  if (starts_with(profile, "cmu_") && profile != "cmu_asf" && std::abs(m.source.file_fps - 120) < 0.1)
    m.diagnostics.note(path, "the cgspeed CMU conversions state 120 Hz for every trial, but some CMU subjects were captured "
                             "at 60 Hz (e.g. the salsa of subjects 60 and 61; see the trial at mocap.cs.cmu.edu); if the "
                             "motion plays twice too fast, pass --source-fps 60");
}

}  // namespace rt
