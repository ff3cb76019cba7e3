#include "src/refine/trajectory_chart.hpp"

#include <gtest/gtest.h>

#include <random>

namespace rt::refine {
namespace {

Mat3 rotation(double yaw, double a, double b) { return root_rotation(yaw, a, b).toRotationMatrix(); }

TEST(TrajectoryChart, RoundTripsConfigurations) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    VecX q(9);
    q << u(rng), u(rng), u(rng), 0, 0, 0, 0, u(rng), u(rng);
    // Any orientation whose tilt stays below 150 deg (the pass refuses to use the chart beyond 144).
    Quat R(AngleAxis(M_PI * u(rng), Vec3::UnitZ()) * AngleAxis(2.6 * std::abs(u(rng)), Vec3(u(rng), u(rng), 0).normalized()));
    if (k % 2) R.coeffs() = -R.coeffs();  // both quaternion signs
    q.segment<4>(3) << R.w(), R.x(), R.y(), R.z();
    const VecX x = chart_from_q(q, 0.0);
    ASSERT_EQ(x.size(), 8);
    VecX q2(9);
    q_from_chart(x, q2);
    EXPECT_TRUE(q2.head<3>().isApprox(q.head<3>()));
    EXPECT_TRUE(q2.tail<2>().isApprox(q.tail<2>()));
    const Quat R2(q2[3], q2[4], q2[5], q2[6]);
    EXPECT_LT(R2.angularDistance(R), 1e-9) << "k = " << k;
    EXPECT_NEAR(std::hypot(x[4], x[5]), tilt_angle(R), 1e-9);
  }
}

TEST(TrajectoryChart, UnwrapsYawAlongATurn) {
  // Three and a half turns about the vertical: the chart's yaw keeps growing.
  double yaw = 0;
  for (int k = 0; k <= 700; ++k) {
    const double truth = k * 0.0314;
    const Quat R(AngleAxis(truth, Vec3::UnitZ()) * AngleAxis(0.1, Vec3::UnitX()));
    yaw = root_yaw(R, yaw);
    EXPECT_NEAR(yaw, truth, 1e-9);
  }
}

TEST(TrajectoryChart, RateMatrixMatchesFiniteDifferences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = 1e-6;
  for (int k = 0; k < 50; ++k) {
    const double yaw = 3 * u(rng), a = u(rng), b = u(rng);
    const Mat3 R = rotation(yaw, a, b);
    const Mat3 M = root_rate_matrix(a, b);
    for (int c = 0; c < 3; ++c) {
      Vec3 d = Vec3::Zero();
      d[c] = h;
      const Mat3 Rp = rotation(yaw + d[0], a + d[1], b + d[2]), Rm = rotation(yaw - d[0], a - d[1], b - d[2]);
      // ω (root frame) = log(Rᵀ R(x + h e_c)) / h, central difference.
      const Vec3 w = (so3_log(R.transpose() * Rp) - so3_log(R.transpose() * Rm)) / (2 * h);
      EXPECT_LT((w - M.col(c)).norm(), 1e-7);
    }
    // Derivatives of the world angular velocity per unit tilt rate.
    std::array<Vec3, 4> dw;
    root_omega_derivatives(yaw, a, b, dw);
    auto omega = [&](double aa, double bb, int j) { return Vec3(rotation(yaw, aa, bb) * root_rate_matrix(aa, bb).col(1 + j)); };
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        const Vec3 fd = i == 0 ? (omega(a + 1e-5, b, j) - omega(a - 1e-5, b, j)) / 2e-5 : (omega(a, b + 1e-5, j) - omega(a, b - 1e-5, j)) / 2e-5;
        EXPECT_LT((fd - dw[static_cast<std::size_t>(2 * i + j)]).norm(), 1e-7);
      }
  }
}

TEST(TrajectoryChart, So3JacobiansMatchFiniteDifferences) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = 1e-6;
  for (int k = 0; k < 50; ++k) {
    const Vec3 phi = Vec3(u(rng), u(rng), u(rng)) * (k < 5 ? 1e-6 : 1.0);
    const Mat3 Jr = so3_right_jacobian(phi), Jl_inv = so3_left_jacobian_inverse(phi);
    const Mat3 R = AngleAxis(phi.norm(), phi.norm() > 0 ? Vec3(phi.normalized()) : Vec3::UnitX()).toRotationMatrix();
    for (int c = 0; c < 3; ++c) {
      const Vec3 e = Vec3::Unit(c) * h;
      const Mat3 Rp = AngleAxis((phi + e).norm(), (phi + e).normalized()).toRotationMatrix();
      const Mat3 Rm = AngleAxis((phi - e).norm(), (phi - e).normalized()).toRotationMatrix();
      // Exp(φ + δ) ≈ Exp(φ) Exp(J_r δ).
      EXPECT_LT(((so3_log(R.transpose() * Rp) - so3_log(R.transpose() * Rm)) / (2 * h) - Jr.col(c)).norm(), 1e-6);
      // log(Exp(δ) Exp(φ)) ≈ φ + J_l⁻¹ δ.
      const Mat3 Ep = AngleAxis(h, Vec3::Unit(c)).toRotationMatrix(), Em = AngleAxis(-h, Vec3::Unit(c)).toRotationMatrix();
      EXPECT_LT(((so3_log(Ep * R) - so3_log(Em * R)) / (2 * h) - Jl_inv.col(c)).norm(), 1e-6);
    }
  }
}

}  // namespace
}  // namespace rt::refine
