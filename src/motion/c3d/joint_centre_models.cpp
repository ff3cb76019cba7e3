#include "retarget/motion/c3d/joint_centre_models.hpp"

#include <algorithm>
#include <cmath>

namespace rt {

std::optional<PelvisFrame> pelvis_frame(const Vec3& lasi, const Vec3& rasi, const Vec3& posterior) {
  const Vec3 origin = 0.5 * (lasi + rasi);
  Vec3 y = lasi - rasi;
  const double width = y.norm();
  if (!(width > 1e-4)) return std::nullopt;
  y /= width;
  Vec3 x = origin - posterior;
  x -= x.dot(y) * y;
  const double depth = x.norm();
  if (!(depth > 1e-4)) return std::nullopt;
  x /= depth;
  PelvisFrame f;
  f.X_F_P.setIdentity();
  f.X_F_P.linear().col(0) = x;
  f.X_F_P.linear().col(1) = y;
  f.X_F_P.linear().col(2) = x.cross(y);
  f.X_F_P.translation() = origin;
  f.pelvis_width_m = width;
  f.pelvis_depth_m = depth;
  return f;
}

Vec3 hip_centre_harrington(double pw, double pd, bool left) {
  const double lateral = 0.33 * pw + 0.0073;
  return {-0.24 * pd - 0.0099, left ? lateral : -lateral, -0.30 * pw - 0.0109};
}

Vec3 hip_centre_davis(double leg_length, double asis_trocanter, double inter_asis, double marker_radius, bool left) {
  constexpr double theta = 0.5;
  constexpr double beta = 0.314;
  const double c = 0.115 * leg_length - 0.0153;
  const double at = asis_trocanter > 0 ? asis_trocanter : 0.1288 * leg_length - 0.04856;
  const double a = 0.5 * inter_asis;
  const double x = c * std::cos(theta) * std::sin(beta) - (at + marker_radius) * std::cos(beta);
  const double lateral = a - c * std::sin(theta);
  const double z = -c * std::cos(theta) * std::cos(beta) - (at + marker_radius) * std::sin(beta);
  return {x, left ? lateral : -lateral, z};
}

Vec3 hip_centre_bell(double pw, bool left) {
  const double lateral = 0.36 * pw;
  return {-0.19 * pw, left ? lateral : -lateral, -0.30 * pw};
}

std::optional<Vec3> chord_joint_centre(const Vec3& p, const Vec3& l, const Vec3& w, double offset, ChordSide side) {
  const Vec3 d = p - l;
  const double dist = d.norm();
  if (!(dist > offset) || !(offset >= 0)) return std::nullopt;
  const Vec3 u = d / dist;
  Vec3 v = (w - l) - (w - l).dot(u) * u;  // in-plane, perpendicular to u, towards W
  const double nv = v.norm();
  if (!(nv > 1e-6)) return std::nullopt;
  v /= nv;
  if (side == ChordSide::AwayFromPlaneMarker) v = -v;
  const double c = offset / dist;
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  return l + offset * (c * u + s * v);
}

std::optional<Vec3> elbow_joint_centre(const Vec3& s, const Vec3& e, const Vec3& w, double offset, bool left) {
  if (!((e - s).norm() > 1e-4) || !((w - e).norm() > 1e-4)) return std::nullopt;
  const Vec3 n = (e - s).cross(w - e);
  if (n.norm() > 1e-9) {
    if (auto j = chord_joint_centre(s, e, e + (left ? 1.0 : -1.0) * n.normalized(), offset, ChordSide::TowardPlaneMarker))
      return j;
  }
  // The marker lies on the line S-M (no plane): it is taken as on the joint's axis already.
  return e;
}

}  // namespace rt
