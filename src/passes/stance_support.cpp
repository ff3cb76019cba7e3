#include "retarget/passes/stance_support.hpp"

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

SupportPolygon stance_support_polygon(const RobotModel& model, const RobotData& data, const std::array<bool, 2>& down) {
  return stance_support_polygon(model, data, down, whole_soles(model));
}

SupportPolygon stance_support_polygon(const RobotModel& model, const RobotData& data, const std::array<bool, 2>& down,
                                      const std::array<SoleReach, 2>& reach) {
  std::vector<Vec2> corners;
  for (int foot = 0; foot < 2; ++foot) {
    if (!down[static_cast<std::size_t>(foot)]) continue;
    const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
    const SoleReach& r = reach[static_cast<std::size_t>(foot)];
    const Iso3 X = link_pose(model, data, sole.link);
    for (const Vec2& s : {r.max_S, Vec2(r.min_S.x(), r.max_S.y()), r.min_S, Vec2(r.max_S.x(), r.min_S.y())})
      corners.push_back((X * (sole.p_L_center + sole.R_L_S * Vec3(s.x(), s.y(), 0))).head<2>());
  }
  return SupportPolygon::convex_hull(std::move(corners));
}

}  // namespace rt
