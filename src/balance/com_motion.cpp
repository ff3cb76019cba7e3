#include "retarget/balance/com_motion.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/core/gaussian_filter.hpp"
#include "retarget/core/limits.hpp"

namespace rt {

std::array<Eigen::Matrix2Xd, 4> com_derivatives(const Eigen::Matrix2Xd& com_W, double rate_hz, double smoothing_s) {
  if (!(smoothing_s >= 0 && smoothing_s <= 10)) throw InputError("reference COM smoothing must be in [0, 10] s");
  check_frame_rate(rate_hz, "reference COM", "the sample rate");
  const auto T = static_cast<int>(com_W.cols());
  const Eigen::Matrix2Xd c = gaussian_filter(com_W, smoothing_s * rate_hz);
  std::array<Eigen::Matrix2Xd, 4> d;
  const double dt = 1.0 / rate_hz;
  for (std::size_t order = 0; order < d.size(); ++order) {
    const Eigen::Matrix2Xd& x = order == 0 ? c : d[order - 1];
    d[order].setZero(2, T);
    for (int k = 0; k < T; ++k) {
      const int a = std::max(0, k - 1), b = std::min(T - 1, k + 1);
      if (b > a) d[order].col(k) = (x.col(b) - x.col(a)) / ((b - a) * dt);
    }
  }
  return d;
}

}  // namespace rt
