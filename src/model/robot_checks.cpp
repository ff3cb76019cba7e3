#include "retarget/model/robot_checks.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

namespace {

double cross2(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Signed distance of p inside the convex hull of `points` (> 0 inside, < 0 outside, the nearest
// edge's distance): Andrew's monotone chain, then the smallest edge distance.
double inside_hull_m(std::vector<Vec2> points, const Vec2& p) {
  std::sort(points.begin(), points.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  std::vector<Vec2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  if (hull.size() < 3) return -1;
  double d = INFINITY;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2& a = hull[i];
    const Vec2& b = hull[(i + 1) % hull.size()];
    const double len = (b - a).norm();
    if (len > 0) d = std::min(d, cross2(a, b, p) / len);  // counter-clockwise: inside is positive
  }
  return d;
}

}  // namespace

Diagnostics check_robot(const RobotModel& model, const RobotCheckOptions& o) {
  Diagnostics out;
  const RobotConfig& c = model.config();
  RobotData data(model);
  update_kinematics(model, data, model.standing_q());

  // Feet: where the soles are at the standing pose.
  std::array<Vec3, 2> centre;
  std::vector<Vec2> support;
  int toes_behind = 0;
  const char* side[2] = {"left", "right"};
  for (int f = 0; f < 2; ++f) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
    const Iso3 X = link_pose(model, data, sole.link);
    centre[static_cast<std::size_t>(f)] = X * sole.p_L_center;
    const Vec3 ahead = centre[static_cast<std::size_t>(f)] - X.translation();
    if (ahead.x() < -o.toes_behind_ankle_m) ++toes_behind;
    const Mat3 R_W_S = X.linear() * sole.R_L_S;
    const double tilt = std::acos(std::clamp(R_W_S(2, 2), -1.0, 1.0));
    const std::string key = c.where(std::string("feet.") + side[f] + ".sole");
    if (tilt > o.max_sole_tilt_rad)
      out.warn(key, format("%s sole: its normal is %.1f deg from vertical at the standing pose (feet not flat: check "
                           "standing_pose, or the sole's link axes when it is given by hand)",
                           side[f], tilt * 180 / M_PI));
    double high = -INFINITY;
    for (const Vec3& corner : sole.corners_L()) {
      const Vec3 p = X * corner;
      high = std::max(high, p.z());
      support.push_back(p.head<2>());
    }
    if (high > o.max_sole_height_m && tilt <= o.max_sole_tilt_rad)
      out.warn(key, format("%s sole: a corner is %.1f mm above the floor at the standing pose (feet not level: check "
                           "standing_pose)", side[f], high * 1e3));
    if (R_W_S.col(0).x() < 0.5)
      out.warn(key, format("%s sole: its length axis points (%.2f, %.2f, %.2f), not forward (+X)", side[f], R_W_S(0, 0),
                           R_W_S(1, 0), R_W_S(2, 0)));
  }
  if (toes_behind == 2)
    out.warn(c.where("base_orientation"),
             "both soles lie behind their ankles along +X: the robot seems to face -X (set base_orientation, e.g. "
             "{forward: -x, up: z})");
  if (centre[0].y() <= centre[1].y())
    out.warn(c.where("feet"), format("the left foot (y = %.3f m) is not to the left of the right foot (y = %.3f m): feet "
                                     "swapped, or the robot does not face +X",
                                     centre[0].y(), centre[1].y()));

  // Balance at the standing pose.
  const Vec3 com = com_position(model, data);
  const double inside = inside_hull_m(support, com.head<2>());
  if (inside < 0)
    out.warn(c.where("standing_pose"), format("the COM (%.3f, %.3f) is %.1f cm outside the feet's support polygon at the "
                                              "standing pose",
                                              com.x(), com.y(), -inside * 100));

  // Limits that look like placeholders.
  std::vector<std::string> fast, no_effort;
  for (int k = 0; k < model.nu(); ++k) {
    const Joint& j = model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(k)])];
    if (j.type != JointType::Prismatic && model.velocity_limits()[k] >= o.placeholder_velocity_rad_s) fast.push_back(j.name);
    if (!(model.effort_limits()[k] > 0)) no_effort.push_back(j.name);
  }
  auto first = [](const std::vector<std::string>& names) {
    std::vector<std::string> some(names.begin(), names.begin() + static_cast<long>(std::min<std::size_t>(names.size(), 6)));
    return join(some, ", ") + (names.size() > 6 ? format(" and %zu more", names.size() - 6) : "");
  };
  if (!fast.empty())
    out.warn(c.urdf_path, format("%zu joint(s) have velocity limits >= %g rad/s, likely placeholders (%s): the pipeline "
                                 "keeps joint speeds under them; override with joint_limits.<joint>.velocity",
                                 fast.size(), o.placeholder_velocity_rad_s, first(fast).c_str()));
  if (!no_effort.empty())
    out.warn(c.urdf_path, format("%zu joint(s) have no effort limit (%s): their motors are unlimited in the check; "
                                 "override with joint_limits.<joint>.effort",
                                 no_effort.size(), first(no_effort).c_str()));

  // Mass and inertia.
  if (model.total_mass_kg() < o.min_mass_kg || model.total_mass_kg() > o.max_mass_kg)
    out.warn(c.urdf_path, format("total mass %.3g kg is implausible for a humanoid (units?)", model.total_mass_kg()));
  for (const Link& l : model.links()) {
    const double m = l.inertial.mass_kg;
    if (!(m > 0)) continue;
    const double I_max = Eigen::SelfAdjointEigenSolver<Mat3>(l.inertial.I_com).eigenvalues().maxCoeff();
    const double k = std::sqrt(std::max(0.0, I_max) / m);
    if (k > o.max_gyration_radius_m || (m > 0.05 && k < o.min_gyration_radius_m))
      out.warn(c.urdf_path, format("link '%s': inertia implausible for its mass (%.3g kg, radius of gyration %.3g m)",
                                   l.name.c_str(), m, k));
  }
  return out;
}

}  // namespace rt
