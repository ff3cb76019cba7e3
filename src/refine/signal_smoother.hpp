#pragma once
/// Zero-phase smoothing of a sampled signal with bounds and a rate limit (private to rt_refine):
///
///   min_x  Σ_f w_f (x_f − y_f)² + λ Σ_f (x_{f−1} − 2 x_f + x_{f+1})²
///   s.t.   lo ≤ x_f ≤ hi,   |x_{f+1} − x_f| ≤ d_max
///
/// The unconstrained problem is a pentadiagonal SPD system (Whittaker–Henderson smoothing, a
/// second-order zero-phase low-pass with |H(ω)| = 1 / (1 + λ (2 − 2 cos ω)²)), solved by a banded
/// LDLᵀ in O(T). The bounds and the rate limit are an active set of quadratic penalties (weight
/// `penalty` per unit², the band structure is kept): each round adds the violated rows, pinned at
/// their bound, and solves again; what the last round still violates is removed by clamping the
/// positions and by a forward-backward rate limiter (at most the solver's tolerance by then).
///
/// Robust smoothing: with `robust_threshold` > 0 the sample weights are re-estimated (iteratively
/// reweighted least squares, Huber): a sample whose residual exceeds robust_threshold · σ, σ the
/// residuals' scale from their median absolute deviation (at least `robust_floor`), is weighted
/// down in proportion, so an isolated spike (a per-frame IK solution on the wrong branch for a few
/// frames) is removed instead of smeared over its neighbours.

#include <vector>

namespace rt::refine {

/// λ whose smoother halves the amplitude at `cutoff_hz` for samples at `fps`.
double smoothing_lambda(double cutoff_hz, double fps);

struct SmoothOptions {
  double lambda = 0;                 ///< second-difference weight (smoothing_lambda)
  double lo = -1e300, hi = 1e300;    ///< position bounds
  double max_step = 1e300;           ///< largest |x_{f+1} − x_f| (rate limit per sample)
  double penalty = 1e8;              ///< weight of a violated bound or rate row
  int max_rounds = 8;
  double robust_threshold = 0;       ///< Huber threshold in units of σ (0: plain least squares)
  double robust_floor = 1e-3;        ///< smallest σ
  int robust_iterations = 4;
};

struct SmoothReport {
  int rounds = 0;
  int active_rows = 0;  ///< bound and rate rows active at the end
  int downweighted = 0; ///< samples weighted down by the robust loss
};

/// Smooths `y` (size T) into `x`.
SmoothReport smooth_signal(const std::vector<double>& y, const SmoothOptions& options, std::vector<double>& x);

/// A curve under per-sample ceilings with a bounded second difference:
///
///   min_x  Σ_f (x_f − y_f)² + λ Σ_f (x_{f−1} − 2 x_f + x_{f+1})²
///   s.t.   x_f ≤ ceiling_f,   −max_fall ≤ x_{f−1} − 2 x_f + x_{f+1} ≤ max_rise  (rows with `curvature_rows[f]`)
///
/// solved by ADMM (the operator splitting of OSQP): every iteration is one pentadiagonal solve, so
/// O(T) per iteration. Unlike the active set of smooth_signal, whose rows stay pinned once active,
/// it releases rows, which a ceiling under a long stretch of samples needs.
struct CeilingOptions {
  double lambda = 0;                ///< second-difference weight (smoothing_lambda)
  std::vector<double> ceiling;      ///< per sample (size T)
  double max_rise = 1e300;          ///< largest second difference (per sample²)
  double max_fall = 1e300;          ///< largest negative second difference (per sample²)
  std::vector<bool> curvature_rows; ///< samples whose second difference is limited (empty: all)
  int max_iterations = 2000;
  double tolerance = 1e-5;          ///< primal and dual residual (the signal's units) to stop at
};

struct CeilingReport {
  int iterations = 0;
  int active = 0;                   ///< samples at their ceiling
  double residual = 0;              ///< largest constraint violation before the final clamp
};

/// Smooths `y` into `x` under the ceilings; what ADMM leaves above a ceiling is clamped.
CeilingReport smooth_under_ceiling(const std::vector<double>& y, const CeilingOptions& options, std::vector<double>& x);

/// Symmetric positive-definite banded system with half-bandwidth 2, solved in place by LDLᵀ:
/// diag[f], off1[f] = A(f, f+1), off2[f] = A(f, f+2). Returns false when not positive definite.
bool solve_pentadiagonal(std::vector<double> diag, std::vector<double> off1, std::vector<double> off2, std::vector<double>& rhs);

}  // namespace rt::refine
