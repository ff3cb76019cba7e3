#pragma once
/// Floor clearance of the robot's collision geometry: every link's URDF collision geometry
/// (including the feet's, which the simulation replaces by sole boxes) reduced to a small set of
/// support points in the link frame, so that "the lowest point of the robot" can be evaluated on
/// every frame of a clip (quality metrics, the refine pass's floor constraints).
///
/// Reduction. The lowest point of a convex body under any rotation is one of its hull vertices, and
/// MuJoCo collides meshes by their convex hulls: a mesh is kept as the vertices of its convex hull
/// (qhull, exact, from the full-resolution URDF mesh; a hull of more than kMaxHullPoints vertices,
/// a finely tessellated curved part, is reduced further to its support points below). Boxes are their 8 corners, spheres exact
/// (centre + radius), cylinders two 32-gons (0.5 % of the radius). Flat meshes, which have no
/// 3-D hull, keep their points extreme along one of kSupportDirections directions spread over the
/// sphere: above the true lowest point by at most r (1 − cos 4.5°), 0.3 mm for r = 10 cm.

#include <array>
#include <utility>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

class RobotModel;
class RobotData;

/// One collision part of a link: support points in the link frame, inflated by `radius_m`
/// (0 except for spheres), and a bounding sphere for cheap culling.
struct CollisionHull {
  int link = -1;
  std::vector<Vec3> points_L;  ///< [m] link frame
  double radius_m = 0;         ///< [m] every point stands for a sphere of this radius
  Vec3 bound_center_L = Vec3::Zero();
  double bound_radius_m = 0;   ///< [m] all of the part lies within this distance of bound_center_L
};

/// Number of directions used to pick support points (see the file comment).
constexpr int kSupportDirections = 1024;
/// Hulls with more vertices than this are reduced to their support points.
constexpr std::size_t kMaxHullPoints = 256;

/// Vertices of the convex hull of a point set (qhull); for a flat or degenerate set, its support
/// points (below).
std::vector<Vec3> convex_hull_vertices(const std::vector<Vec3>& points);

/// Support points of a point set: the points extreme along one of kSupportDirections directions.
std::vector<Vec3> support_points(const std::vector<Vec3>& points);

/// Builds the hull of a set of link-frame points / of a sphere. Fills the bounding sphere.
CollisionHull make_hull(int link, std::vector<Vec3> points_L, double radius_m = 0);

/// The lowest point of the robot's collision geometry at the configuration last given to
/// update_kinematics.
struct LowestPoint {
  double z_m = INFINITY;  ///< [m] height above the floor z = 0 (negative: below)
  int link = -1;          ///< link that owns the geometry
  Vec3 p_L = Vec3::Zero();
  Vec3 p_W = Vec3::Zero();
};
LowestPoint lowest_collision_point(const RobotModel& model, const RobotData& data);

/// Every support point lower than `z_max_m` (links whose bounding sphere stays above it are skipped),
/// appended to `out`; `skip_link` (e.g. a stance foot held on the floor by other means) is left out.
/// The p_W of each point is its surface point (the sphere radius taken off along −z).
void collision_points_below(const RobotModel& model, const RobotData& data, double z_max_m, std::vector<LowestPoint>& out,
                            int skip_link_a = -1, int skip_link_b = -1);

/// The one-sided floor penalty ½ w Σ min(0, z − z_min)² over one link's support points, as
/// Gauss–Newton data in three coordinates: a point p of the link moves up at
/// ż = v_z(o) + ω_x (p − o)_y − ω_y (p − o)_x, o the link origin, so with u = [1, (p−o)_y, −(p−o)_x]
/// the normal equations take Bᵀ M B and Bᵀ m, B = [J_p,z(o); J_ω,x; J_ω,y] (3 rows of the link's
/// Jacobian at its origin), M = Σ w u uᵀ, m = Σ w r u — one Jacobian per link, whatever the number
/// of points below.
struct FloorPenalty {
  int link = -1;
  Vec3 p_W_origin = Vec3::Zero();
  Mat3 M = Mat3::Zero();
  Vec3 m = Vec3::Zero();
  double cost = 0;
  int points = 0;
};

/// The penalties of every link with support points below their minimum height: 0, or the height
/// given for that link in `link_min_height_m`; `skip` links are left out. Appends to `out`.
void floor_penalties(const RobotModel& model, const RobotData& data, double weight,
                     const std::vector<std::pair<int, double>>& link_min_height_m, const std::array<int, 2>& skip,
                     std::vector<FloorPenalty>& out);

}  // namespace rt
