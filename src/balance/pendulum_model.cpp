#include "retarget/balance/pendulum_model.hpp"

namespace rt {

Mat4 PendulumModel::A() const {
  const double w2 = omega_sq();
  Mat4 A;
  A << 0, 0, 1, 0,  //
      0, 0, 0, 1,   //
      w2, -w2, 0, 0,  //
      0, 0, 0, 0;
  return A;
}

Vec4 PendulumModel::B() const { return Vec4(0, 0, 0, 1); }

}  // namespace rt
