#include "retarget/balance/lqr.hpp"

#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

#include "retarget/core/error.hpp"

namespace rt {

MatX solve_care(const MatX& A, const MatX& B, const MatX& Q, const MatX& R) {
  const Eigen::Index n = A.rows();
  RT_DEMAND(A.cols() == n && B.rows() == n && Q.rows() == n && Q.cols() == n && R.rows() == B.cols() &&
                R.cols() == B.cols(),
            "solve_care: inconsistent matrix sizes");
  const MatX R_inv_Bt = R.ldlt().solve(B.transpose());
  MatX H(2 * n, 2 * n);
  H << A, -B * R_inv_Bt, -Q, -A.transpose();

  // The n eigenvectors of the stable eigenvalues span [X1; X2]; P = X2 X1⁻¹.
  Eigen::EigenSolver<MatX> es(H);
  RT_DEMAND(es.info() == Eigen::Success, "solve_care: eigen decomposition failed");
  Eigen::MatrixXcd X(2 * n, n);
  Eigen::Index k = 0;
  for (Eigen::Index i = 0; i < 2 * n; ++i)
    if (es.eigenvalues()[i].real() < 0) {
      RT_DEMAND(k < n, "solve_care: more than n stable eigenvalues");
      X.col(k++) = es.eigenvectors().col(i);
    }
  RT_DEMAND(k == n, "solve_care: the pair (A, B) is not stabilisable");
  const Eigen::MatrixXcd Pc = X.bottomRows(n) * X.topRows(n).inverse();
  MatX P = Pc.real();
  P = 0.5 * (P + P.transpose()).eval();
  RT_DEMAND(P.allFinite(), "solve_care: non-finite solution");
  return P;
}

MatX lqr_gain(const MatX& A, const MatX& B, const MatX& Q, const MatX& R) {
  const MatX P = solve_care(A, B, Q, R);
  return R.ldlt().solve(B.transpose() * P);
}

std::pair<MatX, MatX> discretize_zoh(const MatX& A, const MatX& B, double dt) {
  const Eigen::Index n = A.rows(), m = B.cols();
  // exp([[A, B], [0, 0]] dt) = [[Ad, Bd], [0, I]].
  MatX M = MatX::Zero(n + m, n + m);
  M.topLeftCorner(n, n) = A * dt;
  M.topRightCorner(n, m) = B * dt;
  const MatX E = M.exp();
  return {E.topLeftCorner(n, n), E.topRightCorner(n, m)};
}

}  // namespace rt
