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

// The root height of a double support: a walk's bob with a dip of 4 cm over three frames (the
// legs' reach) at 30 fps; under a ceiling that follows the dip, with the second difference held to
// ±2 m/s², the curve stays under the ceiling, keeps the limit and spreads the dip out.
TEST(CeilingSmoother, StaysUnderTheCeilingWithinTheCurvatureLimits) {
  const double fps = 30, a = 2.0 / (fps * fps);
  const int n = 90;
  std::vector<double> y(n), x;
  CeilingOptions o;
  o.lambda = smoothing_lambda(6, fps);
  o.ceiling.assign(n, 1e300);
  for (int f = 0; f < n; ++f) y[static_cast<std::size_t>(f)] = 0.75 + 0.01 * std::sin(2 * M_PI * 2 * f / fps);
  for (int f = 44; f <= 46; ++f) o.ceiling[static_cast<std::size_t>(f)] = y[static_cast<std::size_t>(f)] - 0.04 + 0.01 * std::abs(f - 45);
  o.max_rise = o.max_fall = a;
  const CeilingReport r = smooth_under_ceiling(y, o, x);
  EXPECT_LT(r.iterations, o.max_iterations);
  EXPECT_GT(r.active, 0);
  for (int f = 0; f < n; ++f) EXPECT_LE(x[static_cast<std::size_t>(f)], o.ceiling[static_cast<std::size_t>(f)]) << f;
  for (int f = 1; f + 1 < n; ++f) {
    const auto k = static_cast<std::size_t>(f);
    EXPECT_LE(std::abs(x[k - 1] - 2 * x[k] + x[k + 1]), a * 1.05 + 1e-6) << f;
  }
  // The dip is spread: going down 4 cm at 2 m/s² takes about 9 frames, so the curve is already
  // more than 1 cm lower 4 frames before the dip, where nothing bounds it, and back on the signal
  // a second away from it.
  EXPECT_LT(x[41], y[41] - 0.01);
  EXPECT_LT(x[49], y[49] - 0.01);
  EXPECT_NEAR(x[10], y[10], 2e-3);
  EXPECT_NEAR(x[80], y[80], 2e-3);
}

// A ceiling under a long stretch must not pin the curve to every sample's ceiling: under a
// jagged ceiling the curve is smooth (the active-set smoother pinned each active row for good).
TEST(CeilingSmoother, AJaggedCeilingIsNotFollowedSampleBySample) {
  const int n = 120;
  std::vector<double> y(n, 1.0), x;
  CeilingOptions o;
  o.lambda = smoothing_lambda(3, 30);
  o.ceiling.resize(n);
  for (int f = 0; f < n; ++f) o.ceiling[static_cast<std::size_t>(f)] = 0.9 + (f % 2 ? 0.05 : 0.0);
  const CeilingReport r = smooth_under_ceiling(y, o, x);
  EXPECT_LT(r.iterations, o.max_iterations);
  // It keeps every ceiling and rides the low ones; between them it may rise a little (the data
  // pull it up, the smoothness weight lets them) but does not follow the 5 cm teeth.
  for (int f = 5; f + 5 < n; ++f) {
    const auto k = static_cast<std::size_t>(f);
    EXPECT_LE(x[k], o.ceiling[k] + 1e-9);
    EXPECT_GT(x[k], 0.9 - 1e-3);
    EXPECT_LT(x[k], 0.905);
  }
  // Unconstrained, it is the Whittaker smoother.
  CeilingOptions free = o;
  free.ceiling.assign(n, 1e300);
  std::vector<double> wave(n), smooth_a, smooth_b;
  for (int f = 0; f < n; ++f) wave[static_cast<std::size_t>(f)] = std::sin(0.4 * f);
  smooth_under_ceiling(wave, free, smooth_a);
  SmoothOptions plain;
  plain.lambda = o.lambda;
  smooth_signal(wave, plain, smooth_b);
  for (int f = 0; f < n; ++f) EXPECT_NEAR(smooth_a[static_cast<std::size_t>(f)], smooth_b[static_cast<std::size_t>(f)], 1e-4) << f;
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
