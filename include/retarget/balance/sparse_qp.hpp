#pragma once
/// Sparse convex quadratic programs with soft linear inequality constraints,
///
///     minimise ½ xᵀ H x + gᵀ x + ½ w Σ_i max(0, a_iᵀ x − b_i)²      (H positive definite),
///
/// by Newton's method on this piecewise quadratic (semismooth Newton / primal active set): solve
/// with the violated rows' penalty, update the set of violated rows, repeat until it no longer
/// changes — then x is the exact minimiser (finite termination; a handful of iterations in
/// practice). Each iteration is one sparse LDLᵀ (Eigen::SimplicialLDLT) of H + w A_vᵀ A_v.
///
/// Written for the whole-clip COM/ZMP plan (zmp_plan.hpp): thousands of unknowns, banded H and a
/// few ZMP half-planes per sample, so each iteration is O(n). The constraints are soft on purpose:
/// where no COM motion can keep the ZMP inside (an angular-momentum burst of the motion) the plan
/// is the least violation, not a failure; where one can, the violation is of the order of the
/// constraint force over w (micrometres for w = 1e6). An interior-point solve of the hard problem
/// was tried first: on badly scaled clips it stalled with its slacks and duals at 1e-26.

#include <Eigen/SparseCore>

#include "retarget/core/types.hpp"

namespace rt {

using SparseMat = Eigen::SparseMatrix<double>;

enum class SparseQpStatus {
  Solved,          ///< the violated set stopped changing: x is the minimiser
  IterationLimit,  ///< stopped at max_iterations (x is the last iterate)
  Failed           ///< a factorisation failed (H not positive definite)
};

const char* sparse_qp_status_name(SparseQpStatus status);

struct SparseQpOptions {
  double penalty = 1e6;   ///< w
  int max_iterations = 50;
};

struct SparseQpResult {
  SparseQpStatus status = SparseQpStatus::Failed;
  int iterations = 0;
  double max_violation = 0;  ///< max(0, max_i (A x − b)_i) at the returned x
  int violated_rows = 0;     ///< rows with a_iᵀx > b_i at the returned x
};

/// H: n x n symmetric positive definite (the lower triangle is read); g: n; A: m x n; b: m. x is the
/// result (n; its input value is ignored).
SparseQpResult solve_sparse_qp(const SparseMat& H, const VecX& g, const SparseMat& A, const VecX& b, VecX& x,
                               const SparseQpOptions& options = {});

}  // namespace rt
