#include "retarget/balance/sparse_qp.hpp"

#include <algorithm>
#include <cmath>

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

namespace {

// Largest α in (0, 1] with v + α dv ≥ 0 (componentwise), times the usual fraction to the boundary.
double step_to_boundary(const VecX& v, const VecX& dv) {
  double alpha = 1.0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (dv[i] < 0) alpha = std::min(alpha, -v[i] / dv[i]);
  return alpha;
}

}  // namespace

SparseQpResult solve_sparse_qp(const SparseMat& H_in, const VecX& g, const SparseMat& A, const VecX& b, VecX& x,
                               const SparseQpOptions& options) {
  const Eigen::Index n = H_in.rows(), m = A.rows();
  RT_DEMAND(H_in.cols() == n && g.size() == n && A.cols() == n && b.size() == m, "solve_sparse_qp: dimensions");
  // Full symmetric H from its lower triangle (callers may store either).
  const SparseMat H_lower = H_in.triangularView<Eigen::Lower>();
  const SparseMat H = SparseMat(H_lower.transpose()) + H_lower - SparseMat(H_in.diagonal().asDiagonal());
  const SparseMat At = A.transpose();
  SparseQpResult result;

  // A tiny diagonal shift keeps a semidefinite H factorisable without changing a definite one's solution
  // noticeably (it is 1e-12 of the mean diagonal).
  const double shift = 1e-12 * std::max(1.0, H.diagonal().cwiseAbs().mean());
  SparseMat I(n, n);
  I.setIdentity();
  Eigen::SimplicialLDLT<SparseMat> ldlt;

  auto factor = [&](const VecX& D) {
    const SparseMat K = H + SparseMat(At * D.asDiagonal() * A) + shift * I;
    ldlt.compute(K);
    return ldlt.info() == Eigen::Success;
  };

  // Start: the unconstrained minimum (D = 0), slacks lifted to at least 1e-2, duals 0.1.
  x.setZero(n);
  if (!factor(VecX::Zero(m))) return result;
  x = ldlt.solve(-g);
  VecX s = (b - A * x).cwiseMax(1e-2);
  VecX z = VecX::Constant(m, 0.1);
  if (m == 0) {
    result.status = SparseQpStatus::Solved;
    return result;
  }

  result.status = SparseQpStatus::IterationLimit;
  const double scale_d = 1.0 + g.cwiseAbs().maxCoeff();
  const double scale_p = 1.0 + b.cwiseAbs().maxCoeff();
  VecX r_d(n), r_p(m), D(m), rhs(n), dx(n), ds(m), dz(m), dx_aff(n), ds_aff(m), dz_aff(m), r_c(m);
  for (int it = 0; it < options.max_iterations; ++it) {
    result.iterations = it;
    r_d = H * x + g + At * z;
    r_p = A * x + s - b;
    const double mu = s.dot(z) / static_cast<double>(m);
    if (r_d.cwiseAbs().maxCoeff() <= options.tolerance * scale_d && r_p.cwiseAbs().maxCoeff() <= options.tolerance * scale_p &&
        mu <= options.tolerance) {
      result.status = SparseQpStatus::Solved;
      break;
    }
    D = z.cwiseQuotient(s);
    if (!factor(D)) {
      result.status = SparseQpStatus::Failed;
      return result;
    }
    // Newton step for the residuals (r_d, r_p, r_c): with Δs = −r_p − AΔx and Δz = S⁻¹(Z r_p − r_c + Z A Δx),
    // (H + AᵀDA) Δx = −r_d − Aᵀ S⁻¹ (Z r_p − r_c).
    auto newton = [&](const VecX& rc, VecX& dxo, VecX& dso, VecX& dzo) {
      rhs = -r_d - At * (z.cwiseProduct(r_p) - rc).cwiseQuotient(s);
      dxo = ldlt.solve(rhs);
      dso = -r_p - A * dxo;
      dzo = (z.cwiseProduct(r_p) - rc + z.cwiseProduct(A * dxo)).cwiseQuotient(s);
    };
    // Predictor (affine scaling), then the centring + second-order corrector.
    r_c = s.cwiseProduct(z);
    newton(r_c, dx_aff, ds_aff, dz_aff);
    const double a_aff = std::min(step_to_boundary(s, ds_aff), step_to_boundary(z, dz_aff));
    const double mu_aff = (s + a_aff * ds_aff).dot(z + a_aff * dz_aff) / static_cast<double>(m);
    const double sigma = std::pow(mu_aff / mu, 3);
    r_c = s.cwiseProduct(z) + ds_aff.cwiseProduct(dz_aff) - VecX::Constant(m, sigma * mu);
    newton(r_c, dx, ds, dz);
    // One step length for primal and dual: in a QP the dual residual depends on x as well.
    const double a = std::min(1.0, 0.995 * std::min(step_to_boundary(s, ds), step_to_boundary(z, dz)));
    x += a * dx;
    s += a * ds;
    z += a * dz;
    result.iterations = it + 1;
  }
  result.max_violation = std::max(0.0, (A * x - b).maxCoeff());
  return result;
}

}  // namespace rt
