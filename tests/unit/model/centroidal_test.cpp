// Centroidal momentum and the multibody ZMP against first principles: link-by-link momenta from
// finite differences of the links' poses and the URDF inertias, and the static / translating cases
// whose ZMP is known in closed form.
#include "retarget/model/centroidal.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>

#include "model_cache.hpp"
#include "support/test_paths.hpp"
#include "retarget/model/kinematics.hpp"

namespace rt {
namespace {

// A smooth whole-body motion: the standing pose with every joint and the root swinging.
VecX pose_at(const RobotModel& model, double t) {
  VecX q = model.standing_q();
  q[0] += 0.3 * t;
  q[1] += 0.05 * std::sin(2 * t);
  q[2] += 0.02 * std::sin(3 * t);
  const Quat R = Quat(AngleAxis(0.3 * std::sin(1.5 * t), Vec3::UnitZ()) * AngleAxis(0.1 * std::sin(2.5 * t), Vec3::UnitX()));
  q.segment<4>(3) << R.w(), R.x(), R.y(), R.z();
  for (int i = 0; i < model.nu(); ++i) {
    const double lo = model.q_lower()[i], hi = model.q_upper()[i];
    const double mid = std::clamp(q[7 + i], lo, hi), amp = 0.2 * std::min(hi - mid, mid - lo);
    q[7 + i] = mid + amp * std::sin((1.0 + 0.1 * i) * t);
  }
  return q;
}

TEST(Centroidal, AngularMomentumEqualsTheSumOverLinks) {
  RT_REQUIRE_SHARED(urdf, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");  // robots/g1 points there
  const RobotModel& model = test::cached_robot("g1");
  RobotData data(model);
  const double t = 0.7, h = 1e-6;
  const VecX q = pose_at(model, t), qa = pose_at(model, t - h), qb = pose_at(model, t + h);
  const VecX v = difference(model, qa, qb, 2 * h);
  const CentroidalMomentum c = centroidal_momentum(model, data, q, v);

  // Σ m_i (x_i − c) × ẋ_i + R_i I_i R_iᵀ ω_i, every link with its own URDF inertial.
  auto link_frames = [&](const VecX& qq) {
    update_kinematics(model, data, qq);
    std::vector<Iso3> X;
    for (std::size_t l = 0; l < model.links().size(); ++l) X.push_back(link_pose(model, data, static_cast<int>(l)));
    return X;
  };
  const std::vector<Iso3> Xa = link_frames(qa), X0 = link_frames(q), Xb = link_frames(qb);
  Vec3 com = Vec3::Zero(), p = Vec3::Zero(), L = Vec3::Zero();
  double mass = 0;
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const Inertial& in = model.links()[l].inertial;
    mass += in.mass_kg;
    com += in.mass_kg * (X0[l] * in.p_L_com);
  }
  com /= mass;
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const Inertial& in = model.links()[l].inertial;
    if (in.mass_kg <= 0) continue;
    const Vec3 x = X0[l] * in.p_L_com, xdot = (Xb[l] * in.p_L_com - Xa[l] * in.p_L_com) / (2 * h);
    const Mat3 dR = (Xb[l].linear() - Xa[l].linear()) / (2 * h);
    const Mat3 W = dR * X0[l].linear().transpose();  // ω× in the world frame
    const Vec3 omega(W(2, 1), W(0, 2), W(1, 0));
    const Mat3 R = X0[l].linear();
    p += in.mass_kg * xdot;
    L += in.mass_kg * (x - com).cross(xdot) + R * in.I_com * R.transpose() * omega;
  }
  EXPECT_LT((c.com_W - com).norm(), 1e-9);
  EXPECT_LT((c.linear_W - p).norm(), 1e-5 * std::max(1.0, p.norm()));
  EXPECT_LT((c.angular_com_W - L).norm(), 1e-5 * std::max(1.0, L.norm())) << c.angular_com_W.transpose() << " vs " << L.transpose();
}

// L = A_L(q) v for any v: the matrix against centroidal_momentum's angular part.
TEST(Centroidal, AngularMatrixTimesVelocityIsTheAngularMomentum) {
  RT_REQUIRE_SHARED(urdf, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");  // robots/g1 points there
  const RobotModel& model = test::cached_robot("g1");
  RobotData data(model);
  const double t = 1.3, h = 1e-6;
  const VecX q = pose_at(model, t);
  const VecX v = difference(model, pose_at(model, t - h), pose_at(model, t + h), 2 * h);
  const CentroidalMomentum c = centroidal_momentum(model, data, q, v);
  update_kinematics(model, data, q);
  const MatX A = centroidal_angular_matrix(model, data);
  ASSERT_EQ(A.rows(), 3);
  ASSERT_EQ(A.cols(), model.nv());
  EXPECT_LT((A * v - c.angular_com_W).norm(), 1e-9 * std::max(1.0, c.angular_com_W.norm()))
      << (A * v).transpose() << " vs " << c.angular_com_W.transpose();
  // The linear rows: the linear momentum, and over the mass the COM Jacobian of MuJoCo's own
  // mj_jacSubtreeCom (one body Jacobian per body).
  const Matrix6X A6 = centroidal_momentum_matrix(model, data);
  EXPECT_LT((A6.topRows<3>() - A).norm(), 1e-12);
  EXPECT_LT((A6.bottomRows<3>() * v - c.linear_W).norm(), 1e-9 * std::max(1.0, c.linear_W.norm()));
  MatXr J(3, model.nv());
  mj_jacSubtreeCom(model.mj(), data.mj(), J.data(), model.root_body());
  EXPECT_LT((com_jacobian(model, data) - MatX(J)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Centroidal, StandingStillHasItsZmpUnderTheCom) {
  RT_REQUIRE_SHARED(urdf, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");  // robots/g1 points there
  const RobotModel& model = test::cached_robot("g1");
  RobotData data(model);
  const MatX q = model.standing_q().replicate(1, 10);
  const MultibodyZmp z = multibody_zmp(model, data, q, 30.0);
  for (int f = 0; f < 10; ++f) EXPECT_LT((z.zmp_W.col(f) - z.com_W.col(f).head<2>()).norm(), 1e-9);
}

// A rigid translation with constant horizontal acceleration a: p = c − c_z a / g exactly (no
// rotation, so no angular momentum rate).
TEST(Centroidal, AcceleratingBodyFollowsTheCartTable) {
  RT_REQUIRE_SHARED(urdf, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");  // robots/g1 points there
  const RobotModel& model = test::cached_robot("g1");
  RobotData data(model);
  const double fps = 100, a = 1.5;
  MatX q = model.standing_q().replicate(1, 20);
  for (int f = 0; f < 20; ++f) q(0, f) += 0.5 * a * (f / fps) * (f / fps);
  const MultibodyZmp z = multibody_zmp(model, data, q, fps);
  for (int f = 1; f < 19; ++f) {
    EXPECT_NEAR(z.zmp_W(0, f), z.com_W(0, f) - z.com_W(2, f) * a / kGravity, 1e-6) << f;
    EXPECT_NEAR(z.zmp_W(1, f), z.com_W(1, f), 1e-9);
  }
}

}  // namespace
}  // namespace rt
