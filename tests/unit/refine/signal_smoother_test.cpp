#include "src/refine/signal_smoother.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "retarget/core/types.hpp"

namespace rt::refine {
namespace {

TEST(SignalSmoother, PentadiagonalSolveMatchesADenseSolve) {
  const int n = 9;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> d(n), e(n, 0.0), c(n, 0.0), b(n);
  MatX A = MatX::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    d[static_cast<std::size_t>(i)] = 5 + u(rng);
    if (i + 1 < n) e[static_cast<std::size_t>(i)] = u(rng);
    if (i + 2 < n) c[static_cast<std::size_t>(i)] = u(rng);
    b[static_cast<std::size_t>(i)] = u(rng);
  }
  for (int i = 0; i < n; ++i) {
    A(i, i) = d[static_cast<std::size_t>(i)];
    if (i + 1 < n) A(i, i + 1) = A(i + 1, i) = e[static_cast<std::size_t>(i)];
    if (i + 2 < n) A(i, i + 2) = A(i + 2, i) = c[static_cast<std::size_t>(i)];
  }
  VecX rhs(n);
  for (int i = 0; i < n; ++i) rhs[i] = b[static_cast<std::size_t>(i)];
  const VecX expected = A.ldlt().solve(rhs);
  ASSERT_TRUE(solve_pentadiagonal(d, e, c, b));
  for (int i = 0; i < n; ++i) EXPECT_NEAR(b[static_cast<std::size_t>(i)], expected[i], 1e-12);
  // Not positive definite.
  std::vector<double> bad = {1, 1, 1};
  EXPECT_FALSE(solve_pentadiagonal({1, -1, 1}, {0, 0, 0}, {0, 0, 0}, bad));
}

// Amplitude of a sinusoid of `hz` after smoothing with a cutoff at `cutoff` (middle of the signal).
double gain(double hz, double cutoff, double fps) {
  const int n = 2000;
  std::vector<double> y(n), x;
  for (int f = 0; f < n; ++f) y[static_cast<std::size_t>(f)] = std::sin(2 * M_PI * hz * f / fps);
  SmoothOptions o;
  o.lambda = smoothing_lambda(cutoff, fps);
  smooth_signal(y, o, x);
  double sum = 0;  // amplitude from the RMS (a few samples per period at 30 fps)
  for (int f = n / 4; f < 3 * n / 4; ++f) sum += x[static_cast<std::size_t>(f)] * x[static_cast<std::size_t>(f)];
  return std::sqrt(2 * sum / (n / 2));
}

TEST(SignalSmoother, HalvesTheAmplitudeAtTheCutoffAtAnyRate) {
  for (const double fps : {30.0, 120.0}) {
    EXPECT_NEAR(gain(6, 6, fps), 0.5, 0.02) << fps;
    EXPECT_GT(gain(1, 6, fps), 0.99) << fps;  // human motion passes
    EXPECT_LT(gain(12, 6, fps), 0.15) << fps;  // noise does not
  }
}

TEST(SignalSmoother, KeepsBoundsAndRateLimitExactly) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.05);
  const int n = 400;
  std::vector<double> y(n), x;
  for (int f = 0; f < n; ++f) y[static_cast<std::size_t>(f)] = 1.2 * std::sin(f * 0.05) + noise(rng);
  y[200] += 2;  // a spike far above the rate limit
  SmoothOptions o;
  o.lambda = smoothing_lambda(6, 120);
  o.lo = -1;
  o.hi = 1;
  o.max_step = 0.02;
  const SmoothReport r = smooth_signal(y, o, x);
  EXPECT_GT(r.active_rows, 0);
  for (int f = 0; f < n; ++f) {
    EXPECT_GE(x[static_cast<std::size_t>(f)], -1.0);
    EXPECT_LE(x[static_cast<std::size_t>(f)], 1.0);
    if (f > 0) {
      EXPECT_LE(std::abs(x[static_cast<std::size_t>(f)] - x[static_cast<std::size_t>(f - 1)]), 0.02 + 1e-12) << f;
    }
  }
  // Away from the bounds and the spike it follows the signal.
  EXPECT_NEAR(x[20], 1.2 * std::sin(1.0), 0.05);
}

TEST(SignalSmoother, RobustLossRemovesASpikeInsteadOfSmearingIt) {
  const int n = 300;
  std::vector<double> y(n), plain, robust;
  for (int f = 0; f < n; ++f) y[static_cast<std::size_t>(f)] = 0.3 * std::sin(f * 0.03);
  for (int f = 150; f < 153; ++f) y[static_cast<std::size_t>(f)] += 0.8;  // 3 frames on the wrong branch
  SmoothOptions o;
  o.lambda = smoothing_lambda(6, 60);
  smooth_signal(y, o, plain);
  o.robust_threshold = 3;
  const SmoothReport r = smooth_signal(y, o, robust);
  EXPECT_GE(r.downweighted, 3);
  EXPECT_GT(std::abs(plain[151] - 0.3 * std::sin(151 * 0.03)), 0.2);
  EXPECT_LT(std::abs(robust[151] - 0.3 * std::sin(151 * 0.03)), 0.02);
  EXPECT_LT(std::abs(robust[50] - 0.3 * std::sin(50 * 0.03)), 1e-3);
}

TEST(SignalSmoother, ShortSignalsAreOnlyClamped) {
  std::vector<double> x;
  SmoothOptions o;
  o.lo = 0;
  o.hi = 1;
  smooth_signal({-1, 2}, o, x);
  EXPECT_EQ(x, (std::vector<double>{0, 1}));
}

}  // namespace
}  // namespace rt::refine
