#pragma once
/// Small dense strictly convex quadratic programs with linear inequality constraints,
///
///     minimise ½ xᵀ H x + gᵀ x   subject to   C x ≥ d      (H positive definite),
///
/// by the dual active-set method of Goldfarb and Idnani (Math. Programming 27, 1983): start at the
/// unconstrained minimum, add the most violated constraint, take primal/dual steps that keep the
/// working set's constraints satisfied with equality and their multipliers non-negative (dropping
/// a constraint whose multiplier would turn negative), until nothing is violated.
///
/// Written for the tracking controller's contact wrenches (12 unknowns, up to 22 constraints, once
/// per control cycle; no QP library ships with Debian). The working set's projections are
/// recomputed from H⁻¹ at each iteration (O(n²k) for k active constraints) instead of being updated
/// by Givens rotations as in QuadProg: simpler, and for n ≲ 40 just as fast and accurate. A dual
/// method needs no feasible starting point, which matters here: the contact constraints are
/// homogeneous cones whose only obvious feasible point (zero force) is their degenerate apex.

#include <vector>

#include <Eigen/Cholesky>

#include "retarget/core/types.hpp"

namespace rt {

enum class QpStatus {
  Solved,          ///< x is the constrained minimum
  Infeasible,      ///< the constraints admit no point (x is the last iterate)
  IterationLimit,  ///< stopped early (x is the last iterate; it satisfies the working set)
  NotConvex        ///< H is not positive definite
};

const char* qp_status_name(QpStatus status);

struct QpOptions {
  /// A constraint counts as violated when C_i x − d_i < −tolerance · ‖C_i‖ · max(1, ‖x‖∞).
  double tolerance = 1e-9;
  int max_iterations = 0;  ///< 0: 3 (n + m)
};

/// Solver with its own workspace: after the first solve of a given size (n, m), solving again
/// allocates nothing.
class DenseQp {
 public:
  /// Solves into x (resized to n). H: n x n symmetric positive definite; g: n; C: m x n; d: m.
  QpStatus solve(const MatX& H, const VecX& g, const MatX& C, const VecX& d, VecX& x, const QpOptions& options = {});

  int iterations() const { return iterations_; }
  /// Constraints in the final working set (indices into the rows of C) and their multipliers.
  const std::vector<int>& active_set() const { return active_; }
  const std::vector<double>& multipliers() const { return u_; }

 private:
  void drop(std::size_t j);

  Eigen::LLT<MatX> llt_;
  MatX H_inv_, N_, HiN_, M_;
  VecX Hn_, z_, r_, rhs_, s_, row_norm_;
  std::vector<int> active_;
  std::vector<double> u_;
  std::vector<char> in_active_;
  int iterations_ = 0;
};

}  // namespace rt
