#include "retarget/model/sole_geometry.hpp"

#include <cmath>

#include "retarget/model/kinematics.hpp"

namespace rt {

std::array<Vec3, 4> sole_corners_W(const Iso3& X_W_sole, const Sole& sole) {
  const double hx = 0.5 * sole.size_m.x(), hy = 0.5 * sole.size_m.y();
  return {X_W_sole * Vec3(hx, hy, 0), X_W_sole * Vec3(-hx, hy, 0), X_W_sole * Vec3(-hx, -hy, 0),
          X_W_sole * Vec3(hx, -hy, 0)};
}

Iso3 flat_on_floor(const Iso3& X) {
  const Vec3 x = X.linear().col(0);
  Iso3 out = Iso3::Identity();
  out.linear() = AngleAxis(std::atan2(x.y(), x.x()), Vec3::UnitZ()).toRotationMatrix();
  out.translation() = Vec3(X.translation().x(), X.translation().y(), 0.0);
  return out;
}

Iso3 sole_frame_W(const RobotModel& model, const RobotData& data, int foot, const Mat3& R_L_sole) {
  const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
  const Iso3 X_link = link_pose(model, data, sole.link);
  Iso3 X = Iso3::Identity();
  X.translation() = X_link * sole.p_L_center;
  X.linear() = X_link.linear() * R_L_sole;
  return X;
}

}  // namespace rt
