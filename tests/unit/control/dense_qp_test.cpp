#include "retarget/control/dense_qp.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include <Eigen/QR>

#include "support/test_paths.hpp"

namespace rt {
namespace {

// Every constraint passes through x* = (1, ..., 1), many more of them than unknowns, and the
// unconstrained minimum (the origin) violates them: the solution is degenerate, with more
// constraints active than the working set can hold. The solver must still end at a point that
// satisfies them all, with at most n constraints in its working set.
TEST(DenseQp, DegenerateVertexWithMoreActiveConstraintsThanUnknowns) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.1, 1.0);
  for (const int n : {2, 3, 6, 12}) {
    const int m = 4 * n;
    const MatX H = MatX::Identity(n, n);
    const VecX g = VecX::Zero(n);
    const VecX x_star = VecX::Ones(n);
    MatX C(m, n);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) C(i, j) = u(rng);  // positive rows: C x* > 0 = C 0, so all violated at 0
    for (int i = 0; i < n; ++i) C.row(m - 1 - i) = C.row(i);  // exact duplicates, too
    const VecX d = C * x_star;
    DenseQp qp;
    VecX x;
    const QpStatus status = qp.solve(H, g, C, d, x);
    ASSERT_EQ(status, QpStatus::Solved) << "n = " << n;
    EXPECT_GE((C * x - d).minCoeff(), -1e-9) << "n = " << n;
    EXPECT_LE(static_cast<int>(qp.active_set().size()), n);
    // x* is feasible, so the minimum norm is at most |x*|.
    EXPECT_LE(x.norm(), x_star.norm() + 1e-9);
  }
}

// Rows that are combinations of a few others, all through one vertex, with a random metric: the
// working set meets linearly dependent rows that rounding makes look independent.
TEST(DenseQp, DependentConstraintsThroughOneVertex) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.0, 1.0);
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = 2 + trial % 40, base = 1 + trial % n, m = 3 * n + 2;
    // A metric as badly scaled as the tracking controller's (weights from 1e-6 to 1e3).
    const Eigen::HouseholderQR<MatX> qr(MatX::Random(n, n));
    const MatX Q = qr.householderQ();
    VecX scale(n);
    for (int i = 0; i < n; ++i) scale[i] = std::pow(10.0, -6.0 + 9.0 * i / std::max(n - 1, 1));
    const MatX H = Q * scale.asDiagonal() * Q.transpose();
    const VecX x_star = VecX::NullaryExpr(n, [&] { return u(rng); });
    MatX B(base, n);
    for (int i = 0; i < base; ++i)
      for (int j = 0; j < n; ++j) B(i, j) = u(rng);
    MatX C(m, n);
    for (int i = 0; i < m; ++i) {
      C.row(i).setZero();
      for (int b = 0; b < base; ++b) C.row(i) += w(rng) * B.row(b);
    }
    const VecX d = C * x_star;
    // The unconstrained minimum far on the infeasible side of the first base row.
    const VecX g = -H * (x_star - 5.0 * B.row(0).transpose());
    DenseQp qp;
    VecX x;
    const QpStatus status = qp.solve(H, g, C, d, x);
    ASSERT_NE(status, QpStatus::NotConvex) << "trial " << trial;
    ASSERT_LE(static_cast<int>(qp.active_set().size()), n) << "trial " << trial;
    if (status == QpStatus::Solved) {
      EXPECT_GE((C * x - d).minCoeff(), -1e-7 * std::max(1.0, x.cwiseAbs().maxCoeff())) << "trial " << trial;
    }
  }
}

// Recorded from the tracking controller (tests/data/qp, an experimental build with joint-acceleration
// rows): the working set held n constraints and rounding let one more in, which wrote past the end
// of the working-set matrices.
TEST(DenseQp, RecordedProblemWithAFullWorkingSet) {
  std::ifstream in(test::source_path("tests/data/qp/full_working_set.txt"));
  ASSERT_TRUE(in) << "missing tests/data/qp/full_working_set.txt";
  std::string comment;
  std::getline(in, comment);
  Eigen::Index n = 0, m = 0;
  in >> n >> m;
  ASSERT_TRUE(in && n > 0 && m > 0);
  MatX H(n, n), C(m, n);
  VecX g(n), d(m);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) in >> H(i, j);
  for (Eigen::Index i = 0; i < n; ++i) in >> g[i];
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) in >> C(i, j);
    in >> d[i];
  }
  ASSERT_TRUE(in);
  DenseQp qp;
  VecX x;
  const QpStatus status = qp.solve(H, g, C, d, x);
  EXPECT_NE(status, QpStatus::NotConvex);
  EXPECT_LE(static_cast<Eigen::Index>(qp.active_set().size()), n);
  if (status == QpStatus::Solved) {
    EXPECT_GE((C * x - d).minCoeff(), -1e-6 * std::max(1.0, x.cwiseAbs().maxCoeff()));
  }
}

TEST(DenseQp, ReportsInfeasibleConstraints) {
  const MatX H = MatX::Identity(2, 2);
  const VecX g = VecX::Zero(2);
  MatX C(2, 2);
  C << 1, 0, -1, 0;  // x0 ≥ 1 and x0 ≤ -1
  const VecX d = (VecX(2) << 1, 1).finished();
  DenseQp qp;
  VecX x;
  EXPECT_EQ(qp.solve(H, g, C, d, x), QpStatus::Infeasible);
}

}  // namespace
}  // namespace rt
