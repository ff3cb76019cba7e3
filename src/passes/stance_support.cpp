#include "retarget/passes/stance_support.hpp"

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

SupportPolygon stance_support_polygon(const RobotModel& model, const RobotData& data, const std::array<bool, 2>& down) {
  std::vector<Vec2> corners;
  for (int foot = 0; foot < 2; ++foot) {
    if (!down[static_cast<std::size_t>(foot)]) continue;
    const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
    const Iso3 X = link_pose(model, data, sole.link);
    for (const Vec3& c : sole.corners_L()) corners.push_back((X * c).head<2>());
  }
  return SupportPolygon::convex_hull(std::move(corners));
}

}  // namespace rt
