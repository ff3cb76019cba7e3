#pragma once
/// Sparse convex quadratic programs with linear inequality constraints,
///
///     minimise ½ xᵀ H x + gᵀ x   subject to   A x ≤ b      (H positive semidefinite),
///
/// by Mehrotra's primal-dual interior-point method (predictor-corrector, one factorisation per
/// iteration; Nocedal & Wright 2006, §16.6). Each iteration solves the normal equations
/// (H + Aᵀ D A) Δx = r with a sparse LDLᵀ (Eigen::SimplicialLDLT) whose pattern is analysed once.
///
/// Written for the whole-clip COM/ZMP plan (zmp_plan.hpp): thousands of unknowns, a banded H (COM
/// tracking + jerk) and a few ZMP half-planes per sample, so H + AᵀDA stays banded and each
/// iteration costs O(n) — milliseconds for a minute of motion, where the dense active-set solver
/// of dense_qp.hpp would be cubic in the clip length. An interior-point method needs no feasible
/// start (slacks absorb the initial violation) and its iteration count barely grows with size.

#include <Eigen/SparseCore>

#include "retarget/core/types.hpp"

namespace rt {

using SparseMat = Eigen::SparseMatrix<double>;

enum class SparseQpStatus {
  Solved,          ///< residuals and complementarity below tolerance
  IterationLimit,  ///< stopped at max_iterations (x is the last iterate, possibly infeasible)
  Failed           ///< the normal equations could not be factorised (H + AᵀDA not positive definite)
};

const char* sparse_qp_status_name(SparseQpStatus status);

struct SparseQpOptions {
  int max_iterations = 60;
  double tolerance = 1e-8;  ///< on the scaled primal and dual residuals and the mean complementarity
};

struct SparseQpResult {
  SparseQpStatus status = SparseQpStatus::Failed;
  int iterations = 0;
  double max_violation = 0;  ///< max(0, max_i (A x − b)_i) at the returned x
};

/// H: n x n symmetric (both triangles stored or only the lower one: the lower triangle is read);
/// g: n; A: m x n; b: m. x is the result (n; its input value is ignored).
SparseQpResult solve_sparse_qp(const SparseMat& H, const VecX& g, const SparseMat& A, const VecX& b, VecX& x,
                               const SparseQpOptions& options = {});

}  // namespace rt
