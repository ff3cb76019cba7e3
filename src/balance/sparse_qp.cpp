#include "retarget/balance/sparse_qp.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/SparseCholesky>

#include "retarget/core/error.hpp"

namespace rt {

const char* sparse_qp_status_name(SparseQpStatus status) {
  switch (status) {
    case SparseQpStatus::Solved: return "solved";
    case SparseQpStatus::IterationLimit: return "iteration limit";
    case SparseQpStatus::Failed: return "factorisation failed";
  }
  return "?";
}

SparseQpResult solve_sparse_qp(const SparseMat& H_in, const VecX& g, const SparseMat& A, const VecX& b, VecX& x,
                               const SparseQpOptions& options) {
  const Eigen::Index n = H_in.rows(), m = A.rows();
  RT_DEMAND(H_in.cols() == n && g.size() == n && A.cols() == n && b.size() == m && options.penalty > 0,
            "solve_sparse_qp: dimensions");
  const SparseMat H_lower = H_in.triangularView<Eigen::Lower>();
  const SparseMat H = SparseMat(H_lower.transpose()) + H_lower - SparseMat(H_in.diagonal().asDiagonal());
  const SparseMat At = A.transpose();
  SparseQpResult result;
  Eigen::SimplicialLDLT<SparseMat> ldlt;

  // The objective at penalty w, and the minimiser of its quadratic model with exactly the rows
  // `active` (0/1) penalised.
  double w = options.penalty;
  auto objective = [&](const VecX& y) {
    const VecX r = (A * y - b).cwiseMax(0.0);
    return 0.5 * y.dot(H * y) + g.dot(y) + 0.5 * w * r.squaredNorm();
  };
  VecX active = VecX::Zero(m), next(m), candidate;
  // K = H + w Σ_active a_i a_iᵀ always lies in the pattern of H + Aᵀ A: that pattern is built and
  // analysed (fill-reducing ordering) once, and each solve only refills its values, H's plus the
  // active rows' outer products (a row of A has a handful of entries). Building K by sparse
  // products on every iteration cost most of a long clip's plan (54 s of 245 s of LAFAN1).
  SparseMat K = H + SparseMat(At * A);
  K.makeCompressed();
  const SparseMat K_H = H + 0.0 * SparseMat(At * A);  // H's values in K's pattern (explicit zeros kept)
  RT_DEMAND(K_H.nonZeros() == K.nonZeros() && std::equal(K_H.innerIndexPtr(), K_H.innerIndexPtr() + K_H.nonZeros(), K.innerIndexPtr()),
            "solve_sparse_qp: pattern");
  ldlt.analyzePattern(K);
  auto solve = [&](VecX& out) {
    std::copy(K_H.valuePtr(), K_H.valuePtr() + K_H.nonZeros(), K.valuePtr());
    for (Eigen::Index i = 0; i < m; ++i) {
      if (active[i] == 0 || w == 0) continue;
      for (SparseMat::InnerIterator p(At, i); p; ++p)
        for (SparseMat::InnerIterator q(At, i); q; ++q) K.coeffRef(p.row(), q.row()) += w * p.value() * q.value();
    }
    ldlt.factorize(K);
    if (ldlt.info() != Eigen::Success) return false;
    out = ldlt.solve(-g + w * (At * active.cwiseProduct(b)));
    return ldlt.info() == Eigen::Success;
  };
  w = 0;
  if (!solve(x)) return result;
  // Continuation: the penalty grows tenfold per stage up to its value, each stage warm-started, so
  // Newton's steps stay short where the objective's kinks are sharp.
  const int stages = 5;
  result.status = SparseQpStatus::Solved;
  for (int stage = stages - 1; stage >= 0 && result.status != SparseQpStatus::Failed; --stage) {
    w = options.penalty * std::pow(10.0, -stage);
    double f = objective(x);
    bool converged = false, full_step = false;
    for (int it = 0; it < options.max_iterations && !converged; ++it) {
      const VecX r = A * x - b;
      for (Eigen::Index i = 0; i < m; ++i) next[i] = r[i] > 0 ? 1.0 : 0.0;
      if (full_step && next == active) {  // x minimises the model of its own violated set: the minimiser
        converged = true;
        break;
      }
      active = next;
      ++result.iterations;
      if (!solve(candidate)) {
        result.status = SparseQpStatus::Failed;
        break;
      }
      // Newton step with backtracking: the full step can overshoot when many rows change at once.
      const VecX d = candidate - x;
      double alpha = 1.0, f_new = objective(candidate);
      while (f_new > f && alpha > 1e-12) {
        alpha *= 0.5;
        f_new = objective(x + alpha * d);
      }
      if (f_new > f) break;  // no descent left: x is the minimiser to rounding (not certified)
      full_step = alpha == 1.0;
      x = full_step ? candidate : VecX(x + alpha * d);
      f = f_new;
    }
    if (!converged && result.status == SparseQpStatus::Solved) result.status = SparseQpStatus::IterationLimit;
  }
  const VecX r = A * x - b;
  result.max_violation = m > 0 ? std::max(0.0, r.maxCoeff()) : 0.0;
  result.violated_rows = static_cast<int>((r.array() > 0).count());
  return result;
}

}  // namespace rt
