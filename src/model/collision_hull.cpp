#include "retarget/model/collision_hull.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

namespace {

// Directions spread evenly over the unit sphere (Fibonacci lattice).
const std::vector<Vec3>& support_directions() {
  static const std::vector<Vec3> dirs = [] {
    std::vector<Vec3> d(kSupportDirections);
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < kSupportDirections; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / kSupportDirections;
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      d[static_cast<std::size_t>(i)] = Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
    return d;
  }();
  return dirs;
}

}  // namespace

namespace {

// qhull of a point set: the hull vertices and, when `planes` is given, the facet planes
// (n · x + d <= 0 inside). False when qhull fails (a flat or degenerate set).
bool run_qhull(const std::vector<Vec3>& points, std::vector<Vec3>* vertices, std::vector<Eigen::Vector4d>* planes) {
  std::vector<coordT> xyz(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) xyz[3 * i + static_cast<std::size_t>(k)] = points[i][k];
  // qhull reports to FILE streams: its messages go to a scratch buffer (library code never prints).
  char* log = nullptr;
  std::size_t log_size = 0;
  FILE* err = open_memstream(&log, &log_size);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  QHULL_LIB_CHECK
  qh_zero(qh, err);
  char options[] = "qhull Qt";
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), xyz.data(), False, options, nullptr, err);
  if (code == 0) {
    if (vertices) {
      vertexT* vertex;
      FORALLvertices {
        const int id = qh_pointid(qh, vertex->point);
        if (id >= 0 && static_cast<std::size_t>(id) < points.size()) vertices->push_back(points[static_cast<std::size_t>(id)]);
      }
    }
    if (planes) {
      facetT* facet;
      FORALLfacets planes->emplace_back(facet->normal[0], facet->normal[1], facet->normal[2], facet->offset);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (err) std::fclose(err);
  std::free(log);
  return code == 0;
}

}  // namespace

std::vector<Vec3> convex_hull_vertices(const std::vector<Vec3>& points) {
  if (points.size() <= 16) return points;
  // Akl–Toussaint: a point strictly inside the hull of a few extreme points is not a hull vertex;
  // dropping those first (most of a mesh) leaves qhull a small remainder.
  std::vector<Vec3> candidates = points;
  std::vector<Vec3> extremes;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) {
        if (a == 0 && b == 0 && c == 0) continue;
        const Vec3 d(a, b, c);
        const Vec3* best = &points.front();
        for (const Vec3& p : points)
          if (p.dot(d) > best->dot(d)) best = &p;
        extremes.push_back(*best);
      }
  std::vector<Eigen::Vector4d> planes;
  if (run_qhull(extremes, nullptr, &planes) && !planes.empty()) {
    double scale = 0;
    for (const Vec3& p : extremes) scale = std::max(scale, p.cwiseAbs().maxCoeff());
    const double eps = 1e-9 * std::max(scale, 1e-3);
    candidates.clear();
    for (const Vec3& p : points) {
      bool inside = true;
      for (const Eigen::Vector4d& pl : planes)
        if (pl.head<3>().dot(p) + pl[3] > -eps) {
          inside = false;
          break;
        }
      if (!inside) candidates.push_back(p);
    }
  }
  std::vector<Vec3> out;
  // Flat or degenerate point sets (qhull needs a full-dimensional hull): keep the extreme points.
  if (candidates.size() > 3 && run_qhull(candidates, &out, nullptr) && !out.empty()) return out;
  return support_points(points);
}

std::vector<Vec3> support_points(const std::vector<Vec3>& points) {
  if (points.size() <= 16) return points;
  std::vector<std::uint8_t> keep(points.size(), 0);
  for (const Vec3& d : support_directions()) {
    std::size_t best = 0;
    double best_dot = -INFINITY;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double s = d.dot(points[i]);
      if (s > best_dot) {
        best_dot = s;
        best = i;
      }
    }
    keep[best] = 1;
  }
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (keep[i]) out.push_back(points[i]);
  return out;
}

CollisionHull make_hull(int link, std::vector<Vec3> points_L, double radius_m) {
  CollisionHull h;
  h.link = link;
  h.points_L = std::move(points_L);
  h.radius_m = radius_m;
  if (h.points_L.empty()) return h;
  Vec3 lo = h.points_L.front(), hi = lo;
  for (const Vec3& p : h.points_L) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  h.bound_center_L = 0.5 * (lo + hi);
  for (const Vec3& p : h.points_L) h.bound_radius_m = std::max(h.bound_radius_m, (p - h.bound_center_L).norm());
  h.bound_radius_m += radius_m;
  return h;
}

namespace {

// Calls visit(hull, X_W_L) for every hull whose bounding sphere reaches below z_max.
template <class Visit>
void for_each_low_hull(const RobotModel& model, const RobotData& data, double z_max, Visit&& visit) {
  int cached_link = -1;
  Iso3 X;
  for (const CollisionHull& h : model.collision_hulls()) {
    if (h.points_L.empty()) continue;
    if (h.link != cached_link) {
      X = link_pose(model, data, h.link);
      cached_link = h.link;
    }
    if ((X * h.bound_center_L).z() - h.bound_radius_m >= z_max) continue;
    visit(h, X);
  }
}

}  // namespace

LowestPoint lowest_collision_point(const RobotModel& model, const RobotData& data) {
  LowestPoint best;
  // Two sweeps: the bound of the feet (nearly always the lowest) culls most other links.
  for (const double z_max : {0.05, static_cast<double>(INFINITY)}) {
    for_each_low_hull(model, data, std::min(z_max, best.z_m), [&](const CollisionHull& h, const Iso3& X) {
      for (const Vec3& p : h.points_L) {
        const Vec3 w = X * p;
        if (w.z() - h.radius_m < best.z_m) {
          best.z_m = w.z() - h.radius_m;
          best.link = h.link;
          best.p_W = w - Vec3(0, 0, h.radius_m);
          best.p_L = X.inverse() * best.p_W;
        }
      }
    });
    if (best.z_m < 0.05) break;
  }
  return best;
}

void collision_points_below(const RobotModel& model, const RobotData& data, double z_max_m, std::vector<LowestPoint>& out,
                            int skip_link_a, int skip_link_b) {
  for_each_low_hull(model, data, z_max_m, [&](const CollisionHull& h, const Iso3& X) {
    if (h.link == skip_link_a || h.link == skip_link_b) return;
    for (const Vec3& p : h.points_L) {
      const Vec3 w = X * p;
      if (w.z() - h.radius_m >= z_max_m) continue;
      LowestPoint lp;
      lp.z_m = w.z() - h.radius_m;
      lp.link = h.link;
      lp.p_W = w - Vec3(0, 0, h.radius_m);
      lp.p_L = X.inverse() * lp.p_W;
      out.push_back(lp);
    }
  });
}

void floor_penalties(const RobotModel& model, const RobotData& data, double weight,
                     const std::vector<std::pair<int, double>>& link_min_height_m, const std::array<int, 2>& skip,
                     std::vector<FloorPenalty>& out) {
  double query = 0;
  for (const auto& [link, z] : link_min_height_m) query = std::max(query, z);
  for_each_low_hull(model, data, query, [&](const CollisionHull& h, const Iso3& X) {
    if (h.link == skip[0] || h.link == skip[1]) return;
    double z_min = 0;
    for (const auto& [link, z] : link_min_height_m)
      if (link == h.link) z_min = z;
    FloorPenalty* pen = nullptr;
    for (const Vec3& p : h.points_L) {
      const Vec3 w = X * p;
      const double r = w.z() - h.radius_m - z_min;
      if (r >= 0) continue;
      if (!pen) {
        // Hulls of one link are consecutive: extend its penalty when it is the last one.
        if (out.empty() || out.back().link != h.link) {
          out.emplace_back();
          out.back().link = h.link;
          out.back().p_W_origin = X.translation();
        }
        pen = &out.back();
      }
      const Vec3 d = w - pen->p_W_origin;
      const Vec3 u(1, d.y(), -d.x());
      pen->M += weight * u * u.transpose();
      pen->m += weight * r * u;
      pen->cost += 0.5 * weight * r * r;
      ++pen->points;
    }
  });
}

}  // namespace rt
