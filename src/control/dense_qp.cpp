#include "retarget/control/dense_qp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "retarget/core/error.hpp"

namespace rt {

const char* qp_status_name(QpStatus status) {
  switch (status) {
    case QpStatus::Solved: return "solved";
    case QpStatus::Infeasible: return "infeasible";
    case QpStatus::IterationLimit: return "iteration limit";
    case QpStatus::NotConvex: return "not convex";
  }
  return "?";
}

void DenseQp::drop(std::size_t j) {
  in_active_[static_cast<std::size_t>(active_[j])] = 0;
  active_.erase(active_.begin() + static_cast<std::ptrdiff_t>(j));
  u_.erase(u_.begin() + static_cast<std::ptrdiff_t>(j));
}

QpStatus DenseQp::solve(const MatX& H, const VecX& g, const MatX& C, const VecX& d, VecX& x, const QpOptions& o) {
  const Eigen::Index n = H.rows(), m = C.rows();
  RT_DEMAND(H.cols() == n && g.size() == n && C.cols() == n && d.size() == m, "DenseQp::solve: inconsistent sizes");
  iterations_ = 0;
  active_.clear();
  u_.clear();
  in_active_.assign(static_cast<std::size_t>(m), 0);
  if (active_.capacity() < static_cast<std::size_t>(n)) {
    active_.reserve(static_cast<std::size_t>(n));
    u_.reserve(static_cast<std::size_t>(n));
  }
  llt_.compute(H);
  if (llt_.info() != Eigen::Success) return QpStatus::NotConvex;
  x = -g;
  llt_.solveInPlace(x);
  if (m == 0) return QpStatus::Solved;
  row_norm_ = C.rowwise().norm();
  bool have_H_inv = false;  // H⁻¹ only once a constraint enters the working set

  N_.resize(n, n);
  HiN_.resize(n, n);
  M_.resize(n, n);
  r_.resize(n);
  rhs_.resize(n);
  const int max_iterations = o.max_iterations > 0 ? o.max_iterations : static_cast<int>(3 * (n + m));
  constexpr double kInf = std::numeric_limits<double>::infinity();

  for (;;) {
    // The most violated constraint (scaled by its row norm) outside the working set.
    s_.noalias() = C * x - d;
    const double x_scale = std::max(1.0, x.cwiseAbs().maxCoeff());
    Eigen::Index p = -1;
    double worst = 0;
    for (Eigen::Index i = 0; i < m; ++i) {
      if (in_active_[static_cast<std::size_t>(i)]) continue;
      const double norm = row_norm_[i];
      if (!(norm > 0)) continue;
      const double scaled = s_[i] / norm;
      if (scaled < -o.tolerance * x_scale && scaled < worst) {
        worst = scaled;
        p = i;
      }
    }
    if (p < 0) return QpStatus::Solved;
    if (!have_H_inv) {
      H_inv_.setIdentity(n, n);
      llt_.solveInPlace(H_inv_);
      have_H_inv = true;
    }

    double u_p = 0;
    for (;;) {
      if (++iterations_ > max_iterations) return QpStatus::IterationLimit;
      const auto k = static_cast<Eigen::Index>(active_.size());
      // Primal direction z = H⁻¹ (I − N (Nᵀ H⁻¹ N)⁻¹ Nᵀ H⁻¹) n_p keeps the working set's constraints
      // unchanged; r = (Nᵀ H⁻¹ N)⁻¹ Nᵀ H⁻¹ n_p is the matching change of their multipliers.
      Hn_.noalias() = H_inv_ * C.row(p).transpose();
      z_ = Hn_;
      auto r = r_.head(k);
      if (k > 0) {
        auto N = N_.leftCols(k);
        auto HiN = HiN_.leftCols(k);
        auto M = M_.topLeftCorner(k, k);
        for (Eigen::Index j = 0; j < k; ++j) N.col(j) = C.row(active_[static_cast<std::size_t>(j)]).transpose();
        HiN.noalias() = H_inv_ * N;
        M.noalias() = N.transpose() * HiN;
        r.noalias() = HiN.transpose() * C.row(p).transpose();
        Eigen::LLT<Eigen::Ref<MatX>> llt_M(M);
        if (llt_M.info() != Eigen::Success) return QpStatus::NotConvex;  // dependent working set: cannot happen in exact arithmetic
        llt_M.solveInPlace(r);
        z_.noalias() -= HiN * r;
      }
      // Dual (partial) step: the largest t keeping the working set's multipliers ≥ 0.
      double t1 = kInf;
      Eigen::Index drop_j = -1;
      for (Eigen::Index j = 0; j < k; ++j) {
        if (r[j] > 0) {
          const double t = u_[static_cast<std::size_t>(j)] / r[j];
          if (t < t1) {
            t1 = t;
            drop_j = j;
          }
        }
      }
      // Primal (full) step: the t that satisfies constraint p with equality. With n constraints in
      // the working set x is pinned (z = 0 up to rounding): p can only enter after a drop, and
      // letting rounding admit it would grow the working set past n.
      const double zn = z_.dot(C.row(p).transpose());
      const double t2 = k < n && zn > 1e-12 * std::max(Hn_.dot(C.row(p).transpose()), 1e-300)
                            ? -(C.row(p).dot(x) - d[p]) / zn
                            : kInf;
      if (t1 == kInf && t2 == kInf) return QpStatus::Infeasible;
      const double t = std::min(t1, t2);
      if (t2 < kInf) x.noalias() += t * z_;
      for (Eigen::Index j = 0; j < k; ++j) u_[static_cast<std::size_t>(j)] = std::max(0.0, u_[static_cast<std::size_t>(j)] - t * r[j]);
      u_p += t;
      if (t2 <= t1) {
        active_.push_back(static_cast<int>(p));
        u_.push_back(u_p);
        in_active_[static_cast<std::size_t>(p)] = 1;
        break;
      }
      drop(static_cast<std::size_t>(drop_j));
    }
  }
}

}  // namespace rt
