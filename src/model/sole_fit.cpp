#include "retarget/model/sole_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rt {

SoleFit fit_sole(const FootSurface& s, const SoleFitOptions& o) {
  SoleFit fit;
  if (s.triangles.empty() || s.vertices_F.empty()) return fit;
  double z_min = std::numeric_limits<double>::infinity();
  for (const Vec3& v : s.vertices_F) z_min = std::min(z_min, v.z());

  // The bottom face's normal: area-weighted over near-horizontal triangles in the lowest band
  // (each turned to point down, so inward-wound meshes give the same answer).
  const double cos_tilt = std::cos(o.max_face_tilt_rad);
  Vec3 n_down = Vec3::Zero();
  for (const auto& t : s.triangles) {
    const Vec3& a = s.vertices_F[static_cast<std::size_t>(t[0])];
    const Vec3& b = s.vertices_F[static_cast<std::size_t>(t[1])];
    const Vec3& c = s.vertices_F[static_cast<std::size_t>(t[2])];
    if (std::min({a.z(), b.z(), c.z()}) > z_min + o.candidate_band_m) continue;
    Vec3 n = (b - a).cross(c - a);  // length: twice the area
    const double len = n.norm();
    if (!(len > 0) || std::abs(n.z()) < cos_tilt * len) continue;
    if (n.z() > 0) n = -n;
    n_down += n;
  }
  const Vec3 up = n_down.norm() > 0 ? Vec3(-n_down.normalized()) : Vec3::UnitZ();

  // Vertices on the face: within the band of the lowest point along the normal.
  double h_min = std::numeric_limits<double>::infinity();
  for (const Vec3& v : s.vertices_F) h_min = std::min(h_min, up.dot(v));
  Vec3 forward = o.forward_F - up * up.dot(o.forward_F);
  if (forward.norm() < 1e-6) forward = Vec3::UnitX() - up * up.x();
  forward.normalize();
  const Vec3 left = up.cross(forward);
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& v : s.vertices_F) {
    if (up.dot(v) > h_min + o.face_band_m) continue;
    const Vec2 p(forward.dot(v), left.dot(v));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    ++fit.face_vertices;
  }
  const Vec2 mid = 0.5 * (lo + hi);
  fit.R_F_S.col(0) = forward;
  fit.R_F_S.col(1) = left;
  fit.R_F_S.col(2) = up;
  fit.p_F_center = forward * mid.x() + left * mid.y() + up * h_min;
  fit.size_m = hi - lo;
  fit.tilt_rad = std::acos(std::clamp(up.z(), -1.0, 1.0));
  return fit;
}

}  // namespace rt
