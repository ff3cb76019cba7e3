#pragma once
/// Support polygon: the convex hull of the sole corners of the links in contact (design.md §3.4),
/// in the horizontal plane of the world frame.

#include <optional>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

/// {p : nᵀ p ≤ d}: n a unit outward normal, d [m].
struct HalfPlane {
  Vec2 n = Vec2::Zero();
  double d = 0;
};

class SupportPolygon {
 public:
  SupportPolygon() = default;
  /// Convex hull of `points_W` (any order, duplicates allowed). Degenerate inputs give a segment
  /// or a single point; no points gives an empty polygon.
  static SupportPolygon convex_hull(std::vector<Vec2> points_W);

  bool empty() const { return vertices_.empty(); }
  /// Hull vertices, counter-clockwise, without repetition.
  const std::vector<Vec2>& vertices() const { return vertices_; }
  double area() const;
  /// Area centroid (vertex mean for degenerate hulls).
  Vec2 centroid() const;

  /// Signed distance [m] from the boundary: negative inside, positive outside. +inf when empty.
  double signed_distance(const Vec2& p) const;
  /// Whether p lies inside, at least margin_m from the boundary (signed_distance(p) ≤ −margin_m).
  bool contains(const Vec2& p, double margin_m = 0.0) const;
  /// The polygon shrunk by margin_m as half-planes (one per edge, outward normals). The margin is
  /// capped at half the distance from the centroid to the nearest edge, so a small polygon shrinks
  /// but never vanishes. Empty for degenerate hulls (fewer than 3 vertices).
  std::vector<HalfPlane> half_planes(double margin_m = 0.0) const;
  /// Closest point on the boundary.
  Vec2 closest_boundary_point(const Vec2& p) const;
  /// Where the segment from `inside` to `outside` leaves the polygon (paper Fig. 6: the border
  /// point between the predicted COP and the new contact). nullopt when `inside` is outside or the
  /// segment never leaves.
  std::optional<Vec2> exit_point(const Vec2& inside, const Vec2& outside) const;

 private:
  std::vector<Vec2> vertices_;
  std::vector<double> edge_length_;  ///< |v[i+1] − v[i]| (hulls of 3 or more vertices)
};

}  // namespace rt
