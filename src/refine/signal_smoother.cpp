#include "src/refine/signal_smoother.hpp"

#include <algorithm>
#include <cmath>

namespace rt::refine {

double smoothing_lambda(double cutoff_hz, double fps) {
  const double w = 2 * M_PI * std::min(cutoff_hz / fps, 0.499);
  const double s = 2 - 2 * std::cos(w);
  return 1.0 / (s * s);
}

bool solve_pentadiagonal(std::vector<double> d, std::vector<double> e, std::vector<double> c, std::vector<double>& b) {
  const std::size_t n = d.size();
  // LDLᵀ with L unit lower triangular, bandwidth 2: l1[i] = L(i+1, i), l2[i] = L(i+2, i).
  std::vector<double> l1(n, 0.0), l2(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (i >= 1) d[i] -= l1[i - 1] * l1[i - 1] * d[i - 1];
    if (i >= 2) d[i] -= l2[i - 2] * l2[i - 2] * d[i - 2];
    if (!(d[i] > 0)) return false;
    if (i + 1 < n) {
      double a = e[i];
      if (i >= 1) a -= l2[i - 1] * l1[i - 1] * d[i - 1];
      l1[i] = a / d[i];
    }
    if (i + 2 < n) l2[i] = c[i] / d[i];
  }
  for (std::size_t i = 0; i < n; ++i) {  // L z = b
    if (i >= 1) b[i] -= l1[i - 1] * b[i - 1];
    if (i >= 2) b[i] -= l2[i - 2] * b[i - 2];
  }
  for (std::size_t i = 0; i < n; ++i) b[i] /= d[i];
  for (std::size_t k = n; k-- > 0;) {  // Lᵀ x = z
    if (k + 1 < n) b[k] -= l1[k] * b[k + 1];
    if (k + 2 < n) b[k] -= l2[k] * b[k + 2];
  }
  return true;
}

namespace {

// One weighted solve with the active set of bounds and rate rows (the header's first paragraph).
SmoothReport solve_weighted(const std::vector<double>& y, const std::vector<double>& w, const SmoothOptions& o,
                            std::vector<double>& x) {
  SmoothReport report;
  const std::size_t n = y.size();
  // Active rows: -1 / +1 at a bound (pos) or a rate limit (rate between f and f+1), 0 inactive.
  std::vector<signed char> pos(n, 0), rate(n - 1, 0);
  for (int round = 0; round < o.max_rounds; ++round) {
    report.rounds = round + 1;
    std::vector<double> d = w, e(n, 0.0), c(n, 0.0), b(n);
    for (std::size_t f = 0; f < n; ++f) b[f] = w[f] * y[f];
    const double L = o.lambda;
    for (std::size_t f = 1; f + 1 < n; ++f) {  // λ (x_{f-1} − 2 x_f + x_{f+1})²
      d[f - 1] += L;
      d[f] += 4 * L;
      d[f + 1] += L;
      e[f - 1] += -2 * L;
      e[f] += -2 * L;
      c[f - 1] += L;
    }
    for (std::size_t f = 0; f < n; ++f)
      if (pos[f]) {
        d[f] += o.penalty;
        b[f] += o.penalty * (pos[f] < 0 ? o.lo : o.hi);
      }
    for (std::size_t f = 0; f + 1 < n; ++f)
      if (rate[f]) {  // penalty (x_{f+1} − x_f − s d_max)²
        d[f] += o.penalty;
        d[f + 1] += o.penalty;
        e[f] -= o.penalty;
        const double s = rate[f] * o.max_step;
        b[f] -= o.penalty * s;
        b[f + 1] += o.penalty * s;
      }
    if (!solve_pentadiagonal(d, e, c, b)) break;  // not reached: identity + λ DᵀD + penalties is positive definite
    x = b;
    bool added = false;
    const double tol_pos = 1e-9;
    for (std::size_t f = 0; f < n; ++f) {
      if (!pos[f] && x[f] < o.lo - tol_pos) pos[f] = -1, added = true;
      if (!pos[f] && x[f] > o.hi + tol_pos) pos[f] = 1, added = true;
    }
    for (std::size_t f = 0; f + 1 < n; ++f) {
      const double step = x[f + 1] - x[f];
      if (!rate[f] && std::abs(step) > o.max_step * (1 + 1e-9)) rate[f] = step > 0 ? 1 : -1, added = true;
    }
    if (!added) break;
  }
  report.active_rows = 0;
  for (signed char p : pos) report.active_rows += p != 0;
  for (signed char r : rate) report.active_rows += r != 0;
  // What the penalties leave (of the order of the solver's tolerance): clamp, then limit the rate
  // forwards and backwards (each pass only moves samples towards their neighbour).
  for (double& v : x) v = std::clamp(v, o.lo, o.hi);
  if (o.max_step < 1e299) {
    for (std::size_t f = 1; f < n; ++f) x[f] = std::clamp(x[f], x[f - 1] - o.max_step, x[f - 1] + o.max_step);
    for (std::size_t f = n - 1; f-- > 0;) x[f] = std::clamp(x[f], x[f + 1] - o.max_step, x[f + 1] + o.max_step);
  }
  return report;
}

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

SmoothReport smooth_signal(const std::vector<double>& y, const SmoothOptions& o, std::vector<double>& x) {
  const std::size_t n = y.size();
  x = y;
  if (n < 3) {
    for (double& v : x) v = std::clamp(v, o.lo, o.hi);
    return {};
  }
  std::vector<double> w(n, 1.0);
  SmoothReport report = solve_weighted(y, w, o, x);
  if (!(o.robust_threshold > 0)) return report;
  std::vector<double> r(n);
  for (int it = 0; it < o.robust_iterations; ++it) {
    for (std::size_t f = 0; f < n; ++f) r[f] = std::abs(y[f] - x[f]);
    const double sigma = std::max(o.robust_floor, 1.4826 * median(r));
    const double limit = o.robust_threshold * sigma;
    int down = 0;
    for (std::size_t f = 0; f < n; ++f) {
      w[f] = r[f] > limit ? limit / r[f] : 1.0;
      down += r[f] > limit;
    }
    report = solve_weighted(y, w, o, x);
    report.downweighted = down;
    if (down == 0) break;
  }
  return report;
}

}  // namespace rt::refine
