#include "retarget/motion/c3d/landmark_gaps.hpp"

#include <algorithm>

namespace rt {

namespace {
bool is_valid(const LandmarkTrack& t, int f) { return t.state[static_cast<std::size_t>(f)] != SampleState::Missing; }
}  // namespace

GapReport fill_gaps(LandmarkTrack& t, int max_gap_frames) {
  GapReport r;
  if (!t.present) return r;
  const int n = static_cast<int>(t.state.size());
  int first = -1, last = -1;
  for (int f = 0; f < n; ++f)
    if (is_valid(t, f)) {
      if (first < 0) first = f;
      last = f;
    }
  if (first < 0) return r;
  r.has_valid = true;
  r.leading = {0, first};
  r.trailing = {last + 1, n};
  for (int f = 0; f < first; ++f) t.p_W.col(f) = t.p_W.col(first);
  for (int f = last + 1; f < n; ++f) t.p_W.col(f) = t.p_W.col(last);
  int f = first;
  while (f <= last) {
    if (is_valid(t, f)) {
      ++f;
      continue;
    }
    const int a = f - 1;  // last valid before the gap
    int b = f;
    while (!is_valid(t, b)) ++b;  // b <= last is valid
    const int len = b - a - 1;
    if (len <= max_gap_frames) {
      // Cubic Hermite on the parameter s in [0, 1] over frames a..b; tangents in units per
      // frame, scaled by the span T = b - a.
      const Vec3 p0 = t.p_W.col(a), p1 = t.p_W.col(b);
      const Vec3 chord = (p1 - p0) / static_cast<double>(b - a);
      const Vec3 m0 = (a - 1 >= 0 && is_valid(t, a - 1)) ? Vec3(p0 - t.p_W.col(a - 1)) : chord;
      const Vec3 m1 = (b + 1 < n && is_valid(t, b + 1)) ? Vec3(t.p_W.col(b + 1) - p1) : chord;
      const double T = static_cast<double>(b - a);
      for (int g = a + 1; g < b; ++g) {
        const double s = static_cast<double>(g - a) / T;
        const double s2 = s * s, s3 = s2 * s;
        t.p_W.col(g) = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * T * m0 + (-2 * s3 + 3 * s2) * p1 +
                       (s3 - s2) * T * m1;
        t.state[static_cast<std::size_t>(g)] = SampleState::Interpolated;
      }
      ++r.filled_gaps;
      r.filled_frames += len;
    } else {
      for (int g = a + 1; g < b; ++g) t.p_W.col(g) = (g - a <= b - g) ? t.p_W.col(a) : t.p_W.col(b);
      r.long_gaps.push_back({a + 1, b});
    }
    f = b;
  }
  return r;
}

FrameGap common_valid_span(const HumanMotion& m, const std::vector<Landmark>& needed) {
  FrameGap span{0, m.num_frames};
  for (Landmark l : needed) {
    const LandmarkTrack& t = m[l];
    if (!t.present) continue;
    int first = -1, last = -1;
    for (int f = 0; f < m.num_frames; ++f)
      if (is_valid(t, f)) {
        if (first < 0) first = f;
        last = f;
      }
    if (first < 0) return {0, 0};
    span.begin = std::max(span.begin, first);
    span.end = std::min(span.end, last + 1);
  }
  return span;
}

void trim_frames(HumanMotion& m, int begin, int end) {
  begin = std::clamp(begin, 0, m.num_frames);
  end = std::clamp(end, begin, m.num_frames);
  const int n = end - begin;
  for (LandmarkTrack& t : m.landmarks) {
    if (!t.present) continue;
    t.p_W = Mat3X(t.p_W.middleCols(begin, n));
    t.state = std::vector<SampleState>(t.state.begin() + begin, t.state.begin() + end);
    if (t.has_orientation) t.R_W = std::vector<Quat>(t.R_W.begin() + begin, t.R_W.begin() + end);
  }
  m.num_frames = n;
}

}  // namespace rt
