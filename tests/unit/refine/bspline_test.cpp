#include "src/refine/bspline.hpp"

#include <gtest/gtest.h>

#include <random>

namespace rt::refine {
namespace {

TEST(BSpline, SupportIsAPartitionOfUnityWithMatchingDerivatives) {
  for (double t = 0; t <= 7.0; t += 0.05) {
    const SplineSupport s = spline_support(t, 10);
    double w = 0, dw = 0;
    for (int m = 0; m < s.count; ++m) {
      w += s.weight[static_cast<std::size_t>(m)];
      dw += s.dweight[static_cast<std::size_t>(m)];
      EXPECT_GE(s.weight[static_cast<std::size_t>(m)], 0.0);
      EXPECT_GE(s.index[static_cast<std::size_t>(m)], 0);
      EXPECT_LT(s.index[static_cast<std::size_t>(m)], 10);
    }
    EXPECT_NEAR(w, 1.0, 1e-12);
    EXPECT_NEAR(dw, 0.0, 1e-12);
  }
  const SplineSupport knot = spline_support(3.0, 10);
  ASSERT_EQ(knot.count, 3);
  EXPECT_EQ(knot.index[0], 3);
  EXPECT_NEAR(knot.weight[1], 4.0 / 6.0, 1e-15);
  EXPECT_NEAR(knot.dweight[0], -0.5, 1e-15);
  EXPECT_NEAR(knot.dweight[2], 0.5, 1e-15);
  EXPECT_EQ(spline_support(7.0, 10).count, 3);  // the last knot uses the last three control points
}

TEST(BSpline, DerivativeWeightsMatchFiniteDifferences) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatX C(2, 9);
  for (int j = 0; j < 9; ++j) C.col(j) << u(rng), u(rng);
  for (double t = 0.1; t < 5.9; t += 0.37) {
    const SplineSupport s = spline_support(t, 9);
    Vec2 d = Vec2::Zero();
    for (int m = 0; m < s.count; ++m) d += s.dweight[static_cast<std::size_t>(m)] * C.col(s.index[static_cast<std::size_t>(m)]);
    const Vec2 fd = (spline_value(C, t + 1e-6) - spline_value(C, t - 1e-6)) / 2e-6;
    EXPECT_LT((d - fd).norm(), 1e-7);
  }
}

// The two properties the refine pass relies on for exact limits at every source frame.
TEST(BSpline, ConvexHullAndVelocityBound) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int stride = 4, N = 20;
  for (int trial = 0; trial < 20; ++trial) {
    MatX C(1, N);
    for (int j = 0; j < N; ++j) C(0, j) = u(rng);
    double max_step = 0;
    for (int j = 0; j + 1 < N; ++j) max_step = std::max(max_step, std::abs(C(0, j + 1) - C(0, j)));
    double prev = spline_value(C, 0)[0];
    for (int f = 1; f <= (N - 3) * stride; ++f) {
      const double x = spline_value(C, static_cast<double>(f) / stride)[0];
      EXPECT_LE(x, C.maxCoeff() + 1e-12);
      EXPECT_GE(x, C.minCoeff() - 1e-12);
      EXPECT_LE(std::abs(x - prev), max_step / stride + 1e-12);  // per frame: at most a stride's share
      prev = x;
    }
  }
}

TEST(BSpline, FitReproducesACubic) {
  const int T = 101, stride = 4;
  MatX samples(1, T);
  auto cubic = [](double f) { return 0.3 - 0.01 * f + 2e-4 * f * f - 1e-6 * f * f * f; };
  for (int f = 0; f < T; ++f) samples(0, f) = cubic(f);
  const MatX C = spline_fit(samples, stride, 0.0);
  EXPECT_EQ(C.cols(), spline_num_controls(T, stride));
  for (int f = 0; f < T; ++f) EXPECT_NEAR(spline_value(C, static_cast<double>(f) / stride)[0], cubic(f), 1e-9);
}

TEST(BSpline, ControlPointCount) {
  EXPECT_EQ(spline_num_controls(101, 4), 28);  // 26 knots (t = 0 .. 25) + 2
  EXPECT_EQ(spline_num_controls(102, 4), 29);  // frame 101 lies inside the 27th knot interval
  EXPECT_EQ(spline_num_controls(2, 1), 4);
}

}  // namespace
}  // namespace rt::refine
