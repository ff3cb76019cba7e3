#include "retarget/model/ankle_reach.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"

namespace rt {

namespace {

// Cuts [lo, hi] to anchor ± reach; an empty result collapses to the anchor clamped into [lo, hi].
void cut(double& lo, double& hi, double anchor, double reach) {
  const double a = std::max(lo, anchor - reach), b = std::min(hi, anchor + reach);
  if (a <= b) {
    lo = a;
    hi = b;
  } else {
    lo = hi = std::clamp(anchor, lo, hi);
  }
}

}  // namespace

std::array<SoleReach, 2> ankle_reach(const RobotModel& model, double load_n) {
  RobotData data(model);
  const VecX q = model.standing_q();
  update_kinematics(model, data, q);
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  update_kinematics(model, data, q);
  const double cos30 = std::cos(M_PI / 6);
  std::array<SoleReach, 2> out = whole_soles(model);
  if (!(load_n > 0)) return out;
  for (int f = 0; f < 2; ++f) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
    SoleReach& r = out[static_cast<std::size_t>(f)];
    const Iso3 X_W_S = sole_frame_W(model, data, f, R_L_sole[static_cast<std::size_t>(f)]);
    const Iso3 X_S_W = X_W_S.inverse();
    int link = sole.link, movable = 0;
    while (link >= 0 && movable < 2) {
      const int j = model.links()[static_cast<std::size_t>(link)].parent_joint;
      if (j < 0) break;
      const Joint& J = model.joints()[static_cast<std::size_t>(j)];
      link = J.parent_link;
      if (J.type == JointType::Fixed) continue;
      if (J.type != JointType::Revolute && J.type != JointType::Continuous) break;
      ++movable;
      if (!(J.effort_limit > 0)) continue;
      const Iso3 X_W_J = link_pose(model, data, J.parent_link) * J.X_P_J;
      const Vec3 axis_S = X_S_W.linear() * (X_W_J.linear() * J.axis);
      const Vec3 anchor_S = X_S_W * X_W_J.translation();
      const double reach = J.effort_limit / load_n;
      if (r.pitch_joint.empty() && std::abs(axis_S.y()) > cos30) {
        cut(r.min_S.x(), r.max_S.x(), anchor_S.x(), reach);
        r.pitch_joint = J.name;
      } else if (r.roll_joint.empty() && std::abs(axis_S.x()) > cos30) {
        cut(r.min_S.y(), r.max_S.y(), anchor_S.y(), reach);
        r.roll_joint = J.name;
      }
    }
  }
  return out;
}

std::array<SoleReach, 2> whole_soles(const RobotModel& model) {
  std::array<SoleReach, 2> out;
  for (std::size_t f = 0; f < 2; ++f) {
    out[f].max_S = 0.5 * model.soles()[f].size_m;
    out[f].min_S = -out[f].max_S;
  }
  return out;
}

std::array<Vec3, 4> reach_corners_W(const Iso3& X, const SoleReach& r) {
  return {X * Vec3(r.max_S.x(), r.max_S.y(), 0), X * Vec3(r.min_S.x(), r.max_S.y(), 0),
          X * Vec3(r.min_S.x(), r.min_S.y(), 0), X * Vec3(r.max_S.x(), r.min_S.y(), 0)};
}

}  // namespace rt
