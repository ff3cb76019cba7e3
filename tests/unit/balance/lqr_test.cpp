#include "retarget/balance/lqr.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "retarget/balance/pendulum_model.hpp"

namespace rt {
namespace {

TEST(Lqr, CareResidualIsZeroAndClosedLoopStable) {
  const PendulumModel m{0.7, 9.81};
  const MatX A = m.A(), B = m.B();
  const MatX Q = Vec4(100, 1, 1, 0.1).asDiagonal().toDenseMatrix();
  const MatX R = MatX::Constant(1, 1, 0.01);
  const MatX P = solve_care(A, B, Q, R);
  const MatX residual = A.transpose() * P + P * A - P * B * R.inverse() * B.transpose() * P + Q;
  EXPECT_LT(residual.norm(), 1e-8 * P.norm());
  EXPECT_TRUE(P.isApprox(P.transpose()));
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(P).eigenvalues().minCoeff(), 0);
  const MatX K = lqr_gain(A, B, Q, R);
  const Eigen::VectorXcd poles = (A - B * K).eigenvalues();
  for (Eigen::Index i = 0; i < poles.size(); ++i) EXPECT_LT(poles[i].real(), 0);
}

TEST(Lqr, ScalarCareMatchesClosedForm) {
  // ẋ = a x + b u: P = (a + sqrt(a² + b² q / r)) r / b².
  const double a = 2, b = 3, q = 5, r = 7;
  const MatX P = solve_care(MatX::Constant(1, 1, a), MatX::Constant(1, 1, b), MatX::Constant(1, 1, q),
                            MatX::Constant(1, 1, r));
  EXPECT_NEAR(P(0, 0), (a + std::sqrt(a * a + b * b * q / r)) * r / (b * b), 1e-12);
}

TEST(Lqr, ZohMatchesEulerForSmallSteps) {
  const PendulumModel m{0.7, 9.81};
  const auto [Ad, Bd] = discretize_zoh(m.A(), m.B(), 1e-6);
  EXPECT_TRUE(Ad.isApprox(Mat4::Identity() + m.A() * 1e-6, 1e-9));
  EXPECT_TRUE(Bd.isApprox(m.B() * 1e-6, 1e-5));
  // Double integrator over 1 s with unit input: exact answer known.
  MatX A2(2, 2), B2(2, 1);
  A2 << 0, 1, 0, 0;
  B2 << 0, 1;
  const auto [Ad2, Bd2] = discretize_zoh(A2, B2, 1.0);
  EXPECT_NEAR(Ad2(0, 1), 1.0, 1e-12);
  EXPECT_NEAR(Bd2(0, 0), 0.5, 1e-12);
  EXPECT_NEAR(Bd2(1, 0), 1.0, 1e-12);
}

}  // namespace
}  // namespace rt
