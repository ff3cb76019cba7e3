#include "retarget/core/gaussian_filter.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rt {

MatX gaussian_filter(const MatX& x, double sigma) {
  const auto T = static_cast<int>(x.cols());
  if (!(sigma > 1e-3) || T < 2) return x;
  // Beyond the clip's length every tap reads an end sample: no wider kernel than the clip (a huge
  // rate made the kernel, and the loop over it, unbounded).
  const int half = static_cast<int>(std::min(std::ceil(3 * std::min(sigma, 1e6)), static_cast<double>(T)));
  std::vector<double> kernel(static_cast<std::size_t>(2 * half + 1));
  double sum = 0;
  for (int i = -half; i <= half; ++i) sum += kernel[static_cast<std::size_t>(i + half)] = std::exp(-0.5 * i * i / (sigma * sigma));
  for (double& k : kernel) k /= sum;
  MatX out = MatX::Zero(x.rows(), T);
  for (int k = 0; k < T; ++k)
    for (int i = -half; i <= half; ++i) out.col(k) += kernel[static_cast<std::size_t>(i + half)] * x.col(std::clamp(k + i, 0, T - 1));
  return out;
}

}  // namespace rt
