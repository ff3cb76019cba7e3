#include "retarget/balance/support_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rt {

namespace {

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

Vec2 closest_on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  if (len2 <= 0) return a;
  const double t = std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
  return a + t * d;
}

}  // namespace

SupportPolygon SupportPolygon::convex_hull(std::vector<Vec2> pts) {
  SupportPolygon poly;
  std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  pts.erase(std::unique(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1e-12; }),
            pts.end());
  if (pts.size() < 3) {
    poly.vertices_ = pts;
    return poly;
  }
  // Andrew's monotone chain.
  std::vector<Vec2> hull(2 * pts.size());
  std::size_t k = 0;
  for (const Vec2& p : pts) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 1e-15) --k;
    hull[k++] = p;
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 1e-15) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  poly.vertices_ = std::move(hull);
  const std::size_t n = poly.vertices_.size();
  poly.edge_length_.resize(n);
  for (std::size_t i = 0; i < n; ++i) poly.edge_length_[i] = (poly.vertices_[(i + 1) % n] - poly.vertices_[i]).norm();
  return poly;
}

bool SupportPolygon::contains(const Vec2& p, double margin_m) const {
  const std::size_t n = vertices_.size();
  if (n < 3 || margin_m < 0) return signed_distance(p) <= -margin_m;
  // Inside a convex polygon the distance to the boundary is the least distance to an edge's line:
  // p qualifies when it lies at least margin_m to the left of every (counter-clockwise) edge.
  for (std::size_t i = 0; i < n; ++i)
    if (cross(vertices_[i], vertices_[(i + 1) % n], p) < margin_m * edge_length_[i]) return false;
  return true;
}

std::vector<HalfPlane> SupportPolygon::half_planes(double margin_m) const {
  std::vector<HalfPlane> out;
  const std::size_t n = vertices_.size();
  if (n < 3) return out;
  const Vec2 c = centroid();
  double inner = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e = vertices_[(i + 1) % n] - vertices_[i];
    HalfPlane h;
    h.n = Vec2(e.y(), -e.x()) / edge_length_[i];  // right of a counter-clockwise edge: outward
    h.d = h.n.dot(vertices_[i]);
    inner = std::min(inner, h.d - h.n.dot(c));
    out.push_back(h);
  }
  const double margin = std::clamp(margin_m, 0.0, 0.5 * std::max(inner, 0.0));
  for (HalfPlane& h : out) h.d -= margin;
  return out;
}

double SupportPolygon::area() const {
  double a = 0;
  const std::size_t n = vertices_.size();
  for (std::size_t i = 0; n >= 3 && i < n; ++i) {
    const Vec2& p = vertices_[i];
    const Vec2& q = vertices_[(i + 1) % n];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

Vec2 SupportPolygon::centroid() const {
  const std::size_t n = vertices_.size();
  if (n == 0) return Vec2::Zero();
  const double a = area();
  if (n < 3 || a < 1e-12) {
    Vec2 m = Vec2::Zero();
    for (const Vec2& v : vertices_) m += v;
    return m / static_cast<double>(n);
  }
  Vec2 c = Vec2::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& p = vertices_[i];
    const Vec2& q = vertices_[(i + 1) % n];
    const double w = p.x() * q.y() - q.x() * p.y();
    c += (p + q) * w;
  }
  return c / (6.0 * a);
}

Vec2 SupportPolygon::closest_boundary_point(const Vec2& p) const {
  const std::size_t n = vertices_.size();
  if (n == 0) return p;
  if (n == 1) return vertices_[0];
  Vec2 best = vertices_[0];
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 c = closest_on_segment(vertices_[i], vertices_[(i + 1) % n], p);
    const double d = (c - p).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

double SupportPolygon::signed_distance(const Vec2& p) const {
  if (vertices_.empty()) return std::numeric_limits<double>::infinity();
  const double d = (closest_boundary_point(p) - p).norm();
  if (vertices_.size() < 3) return d;
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    if (cross(vertices_[i], vertices_[(i + 1) % vertices_.size()], p) < 0) return d;  // right of an edge: outside
  return -d;
}

std::optional<Vec2> SupportPolygon::exit_point(const Vec2& inside, const Vec2& outside) const {
  if (vertices_.size() < 3 || signed_distance(inside) > 0) return std::nullopt;
  const Vec2 d = outside - inside;
  double t_exit = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    const Vec2& a = vertices_[i];
    const Vec2 e = vertices_[(i + 1) % vertices_.size()] - a;
    const Vec2 outward(e.y(), -e.x());  // CCW polygon: right-hand normal points out
    const double denom = outward.dot(d);
    if (denom <= 1e-15) continue;  // moving along or into this edge's half-plane
    const double t = outward.dot(a - inside) / denom;
    t_exit = std::min(t_exit, std::max(t, 0.0));
  }
  if (!(t_exit <= 1.0)) return std::nullopt;
  return inside + t_exit * d;
}

}  // namespace rt
