#include "retarget/motion/c3d/marker_trajectories.hpp"

#include "retarget/core/strings.hpp"

namespace rt {

std::string normalise_marker_name(std::string_view label) {
  const auto colon = label.rfind(':');
  if (colon != std::string_view::npos) label = label.substr(colon + 1);
  // Upper case without blanks: Elite/BTS systems write 'r asis' for RASIS.
  std::string out;
  for (char c : trim(label)) {
    if (c == ' ') continue;
    out.push_back(c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c);
  }
  return out;
}

int MarkerTrajectories::find(std::string_view name) const {
  if (name.empty()) return -1;
  for (std::size_t i = 0; i < markers.size(); ++i)
    if (markers[i].name == name) return static_cast<int>(i);
  return -1;
}

MarkerTrajectories marker_trajectories(const c3d::C3dFile& file, double metres_per_unit) {
  MarkerTrajectories out;
  const c3d::PointSamples& ps = file.points;
  out.num_frames = ps.num_frames;
  const int frames = ps.num_frames;
  for (int i = 0; i < ps.num_points; ++i) {
    if (file.point_kinds[static_cast<std::size_t>(i)] != c3d::PointKind::Marker) continue;
    MarkerTrajectory m;
    m.label = file.point_labels[static_cast<std::size_t>(i)];
    m.name = normalise_marker_name(m.label);
    m.point_index = i;
    m.p_F.setZero(3, frames);
    m.state.assign(static_cast<std::size_t>(frames), SampleState::Missing);
    int last = -1;
    for (int f = 0; f < frames; ++f) {
      if (!ps.valid(f, i)) continue;
      const float* p = ps.at(f, i);
      const Vec3 v = Vec3(p[0], p[1], p[2]) * metres_per_unit;
      if (!(v.cwiseAbs().maxCoeff() <= kMaxMarkerDistance_m)) {
        ++out.implausible_samples;
        continue;
      }
      m.p_F.col(f) = v;
      m.state[static_cast<std::size_t>(f)] = SampleState::Measured;
      // Hold the last valid sample through the gap before f (nearest of the two ends).
      for (int g = last + 1; g < f; ++g)
        m.p_F.col(g) = (last < 0 || f - g <= g - last) ? m.p_F.col(f) : m.p_F.col(last);
      last = f;
    }
    if (last >= 0)
      for (int g = last + 1; g < frames; ++g) m.p_F.col(g) = m.p_F.col(last);
    out.markers.push_back(std::move(m));
  }
  return out;
}

}  // namespace rt
