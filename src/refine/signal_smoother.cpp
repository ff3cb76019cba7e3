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

// Adds weight · Σ_f (x_{f−1} − 2 x_f + x_{f+1})² to a pentadiagonal matrix (diag, off1, off2 as in
// solve_pentadiagonal).
void add_second_differences(double weight, std::vector<double>& d, std::vector<double>& e, std::vector<double>& c) {
  for (std::size_t f = 1; f + 1 < d.size(); ++f) {
    d[f - 1] += weight;
    d[f] += 4 * weight;
    d[f + 1] += weight;
    e[f - 1] += -2 * weight;
    e[f] += -2 * weight;
    c[f - 1] += weight;
  }
}

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
    add_second_differences(o.lambda, d, e, c);
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

CeilingReport smooth_under_ceiling(const std::vector<double>& y, const CeilingOptions& o, std::vector<double>& x) {
  CeilingReport report;
  const std::size_t n = y.size();
  x = y;
  if (n < 3 || o.ceiling.size() != n) {
    for (std::size_t f = 0; f < n && f < o.ceiling.size(); ++f) x[f] = std::min(x[f], o.ceiling[f]);
    return report;
  }
  // Constraint rows A x: the n samples, then the n second differences (rows 0 and n-1 unbounded).
  std::vector<double> lo(2 * n, -1e300), hi(2 * n, 1e300);
  for (std::size_t f = 0; f < n; ++f) hi[f] = o.ceiling[f];
  for (std::size_t f = 1; f + 1 < n; ++f)
    if (o.curvature_rows.size() != n || o.curvature_rows[f]) lo[n + f] = -o.max_fall, hi[n + f] = o.max_rise;
  auto apply_A = [&](const std::vector<double>& v, std::vector<double>& out) {
    out.assign(2 * n, 0.0);
    for (std::size_t f = 0; f < n; ++f) out[f] = v[f];
    for (std::size_t f = 1; f + 1 < n; ++f) out[n + f] = v[f - 1] - 2 * v[f] + v[f + 1];
  };
  auto apply_At = [&](const std::vector<double>& w, std::vector<double>& out) {
    out.assign(n, 0.0);
    for (std::size_t f = 0; f < n; ++f) out[f] = w[f];
    for (std::size_t f = 1; f + 1 < n; ++f) {
      out[f - 1] += w[n + f];
      out[f] -= 2 * w[n + f];
      out[f + 1] += w[n + f];
    }
  };
  // ½ xᵀ P x + qᵀ x with P = 2 (I + λ D₂ᵀD₂), q = −2 y; the ADMM matrix P + σ I + ρ AᵀA, where
  // AᵀA = I + D₂ᵀD₂, is pentadiagonal.
  const double sigma = 1e-6, rho = 2 * (1 + o.lambda), alpha = 1.6;
  const double a_d = 2 + sigma + rho, a_dd = 2 * o.lambda + rho;  // identity and D₂ᵀD₂ parts
  std::vector<double> diag(n, a_d), off1(n, 0.0), off2(n, 0.0);
  add_second_differences(a_dd, diag, off1, off2);
  std::vector<double> z, u(2 * n, 0.0), w(2 * n), rhs(n), At, Ax, z_prev;
  apply_A(x, z);
  for (std::size_t i = 0; i < 2 * n; ++i) z[i] = std::clamp(z[i], lo[i], hi[i]);
  for (int it = 0; it < o.max_iterations; ++it) {
    report.iterations = it + 1;
    for (std::size_t i = 0; i < 2 * n; ++i) w[i] = rho * z[i] - u[i];
    apply_At(w, At);
    for (std::size_t f = 0; f < n; ++f) rhs[f] = sigma * x[f] + 2 * y[f] + At[f];
    if (!solve_pentadiagonal(diag, off1, off2, rhs)) break;  // not reached: the matrix is positive definite
    x = rhs;
    apply_A(x, Ax);
    z_prev = z;
    double primal = 0, dual = 0;
    for (std::size_t i = 0; i < 2 * n; ++i) {
      const double relaxed = alpha * Ax[i] + (1 - alpha) * z_prev[i];
      z[i] = std::clamp(relaxed + u[i] / rho, lo[i], hi[i]);
      u[i] += rho * (relaxed - z[i]);
      primal = std::max(primal, std::abs(Ax[i] - z[i]));
      dual = std::max(dual, std::abs(z[i] - z_prev[i]));
    }
    report.residual = primal;
    if (primal < o.tolerance && dual < o.tolerance) break;
  }
  for (std::size_t f = 0; f < n; ++f) {
    report.active += x[f] >= o.ceiling[f] - 10 * o.tolerance;
    x[f] = std::min(x[f], o.ceiling[f]);
  }
  return report;
}

}  // namespace rt::refine
