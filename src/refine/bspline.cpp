#include "src/refine/bspline.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <vector>

#include "retarget/core/error.hpp"

namespace rt::refine {

SplineSupport spline_support(double t, int num_controls) {
  RT_DEMAND(num_controls >= 4, "a cubic B-spline needs at least 4 control points");
  const int last_segment = num_controls - 4;
  int i = static_cast<int>(std::floor(t));
  i = std::clamp(i, 0, last_segment);
  const double u = std::clamp(t - i, 0.0, 1.0);
  const double u2 = u * u, u3 = u2 * u, v = 1.0 - u;
  const std::array<double, 4> w = {v * v * v / 6.0, (3 * u3 - 6 * u2 + 4) / 6.0, (-3 * u3 + 3 * u2 + 3 * u + 1) / 6.0,
                                   u3 / 6.0};
  const std::array<double, 4> dw = {-0.5 * v * v, 1.5 * u2 - 2 * u, -1.5 * u2 + u + 0.5, 0.5 * u2};
  SplineSupport s;
  for (int m = 0; m < 4; ++m) {
    const auto k = static_cast<std::size_t>(m);
    if (std::abs(w[k]) < 1e-14 && std::abs(dw[k]) < 1e-14) continue;
    s.index[static_cast<std::size_t>(s.count)] = i + m;
    s.weight[static_cast<std::size_t>(s.count)] = w[k];
    s.dweight[static_cast<std::size_t>(s.count)] = dw[k];
    ++s.count;
  }
  return s;
}

int spline_num_controls(int num_frames, int stride) {
  RT_DEMAND(num_frames >= 1 && stride >= 1, "spline_num_controls: bad arguments");
  const int knots = (num_frames - 1 + stride - 1) / stride + 1;
  return std::max(knots, 2) + 2;
}

VecX spline_value(const MatX& controls, double t) {
  const SplineSupport s = spline_support(t, static_cast<int>(controls.cols()));
  VecX x = VecX::Zero(controls.rows());
  for (int m = 0; m < s.count; ++m) x += s.weight[static_cast<std::size_t>(m)] * controls.col(s.index[static_cast<std::size_t>(m)]);
  return x;
}

MatX spline_fit(const MatX& samples, int stride, double smoothing) {
  const int T = static_cast<int>(samples.cols());
  const int N = spline_num_controls(T, stride);
  // Normal equations (BᵀB + s DᵀD) C = Bᵀ X, banded (bandwidth 3), shared by every coordinate.
  std::vector<Eigen::Triplet<double>> entries;
  MatX rhs = MatX::Zero(N, samples.rows());
  for (int f = 0; f < T; ++f) {
    const SplineSupport s = spline_support(static_cast<double>(f) / stride, N);
    for (int a = 0; a < s.count; ++a) {
      const int ia = s.index[static_cast<std::size_t>(a)];
      const double wa = s.weight[static_cast<std::size_t>(a)];
      rhs.row(ia) += wa * samples.col(f).transpose();
      for (int b = 0; b < s.count; ++b)
        entries.emplace_back(ia, s.index[static_cast<std::size_t>(b)], wa * s.weight[static_cast<std::size_t>(b)]);
    }
  }
  const double lambda = smoothing * std::max(1.0, static_cast<double>(stride));
  for (int j = 1; j + 1 < N; ++j) {
    const int idx[3] = {j - 1, j, j + 1};
    const double c[3] = {1, -2, 1};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) entries.emplace_back(idx[a], idx[b], lambda * c[a] * c[b]);
  }
  Eigen::SparseMatrix<double> A(N, N);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  RT_DEMAND(ldlt.info() == Eigen::Success, "spline_fit: normal equations are singular");
  const MatX C = ldlt.solve(rhs);
  return C.transpose();
}

}  // namespace rt::refine
