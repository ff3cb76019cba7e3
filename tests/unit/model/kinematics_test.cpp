// Kinematics/dynamics API over MuJoCo, checked against finite differences in random moving states
// (on the test robot always, and on the real robots when the shared data is present).

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "model_cache.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// Random configuration (joints inside their limits, any root orientation) and velocity.
void random_state(const RobotModel& r, std::mt19937& rng, VecX& q, VecX& v) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> n(0, 1);
  q = r.standing_q();
  q.head<3>() += Vec3(u(rng), u(rng), u(rng));
  const Quat root = Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
  q.segment<4>(3) << root.w(), root.x(), root.y(), root.z();
  for (int k = 0; k < r.nu(); ++k) {
    const double lo = std::max(r.q_lower()[k], -1.5), hi = std::min(r.q_upper()[k], 1.5);
    q[7 + k] = lo + (hi - lo) * 0.5 * (u(rng) + 1);
  }
  v.resize(r.nv());
  for (int i = 0; i < r.nv(); ++i) v[i] = n(rng);
}

// Angular velocity taking R0 to R1 in time dt (world frame).
Vec3 angular_velocity(const Mat3& R0, const Mat3& R1, double dt) {
  const AngleAxis aa(R1 * R0.transpose());
  return aa.axis() * aa.angle() / dt;
}

void check_jacobians(const RobotModel& r, int seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  RobotData data(r);
  VecX q, v;
  random_state(r, rng, q, v);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  const double h = 1e-6;
  const VecX q_plus = integrate(r, q, v, h), q_minus = integrate(r, q, v, -h);

  for (int link = 0; link < static_cast<int>(r.links().size()); ++link) {
    SCOPED_TRACE(r.links()[static_cast<std::size_t>(link)].name);
    const Vec3 p_L(u(rng), u(rng), u(rng));
    update_kinematics(r, data, q_plus);
    const Iso3 X_plus = link_pose(r, data, link);
    update_kinematics(r, data, q_minus);
    const Iso3 X_minus = link_pose(r, data, link);
    update_kinematics(r, data, q);
    const MatX J = link_jacobian(r, data, link, p_L);
    ASSERT_EQ(J.rows(), 6);
    ASSERT_EQ(J.cols(), r.nv());
    const Vec3 v_fd = (X_plus * p_L - X_minus * p_L) / (2 * h);
    const Vec3 w_fd = angular_velocity(X_minus.linear(), X_plus.linear(), 2 * h);
    const Vec6 Jv = J * v;
    EXPECT_LT((Jv.head<3>() - v_fd).norm(), 1e-6 * (1 + v_fd.norm())) << Jv.head<3>().transpose() << " vs " << v_fd.transpose();
    EXPECT_LT((Jv.tail<3>() - w_fd).norm(), 1e-6 * (1 + w_fd.norm())) << Jv.tail<3>().transpose() << " vs " << w_fd.transpose();
    EXPECT_TRUE(link_point(r, data, link, p_L).isApprox(link_pose(r, data, link) * p_L));
  }

  // COM and its Jacobian.
  update_kinematics(r, data, q_plus);
  const Vec3 c_plus = com_position(r, data);
  update_kinematics(r, data, q_minus);
  const Vec3 c_minus = com_position(r, data);
  update_kinematics(r, data, q);
  const MatX Jc = com_jacobian(r, data);
  ASSERT_EQ(Jc.rows(), 3);
  const Vec3 vc_fd = (c_plus - c_minus) / (2 * h);
  EXPECT_LT((Jc * v - vc_fd).norm(), 1e-6 * (1 + vc_fd.norm()));
}

void check_jdot_v(const RobotModel& r, int seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  RobotData data(r);
  VecX q, v;
  random_state(r, rng, q, v);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  // Along q(t) = integrate(q, v, t) with v constant (q̈ = 0): d/dt (J(q) v) = J̇ v.
  const double h = 1e-5;
  const VecX q_plus = integrate(r, q, v, h), q_minus = integrate(r, q, v, -h);
  for (int link = 0; link < static_cast<int>(r.links().size()); ++link) {
    SCOPED_TRACE(r.links()[static_cast<std::size_t>(link)].name);
    const Vec3 p_L(u(rng), u(rng), u(rng));
    update_kinematics(r, data, q_plus);
    const Vec6 Jv_plus = link_jacobian(r, data, link, p_L) * v;
    update_kinematics(r, data, q_minus);
    const Vec6 Jv_minus = link_jacobian(r, data, link, p_L) * v;
    const Vec6 fd = (Jv_plus - Jv_minus) / (2 * h);
    update_dynamics(r, data, q, v);
    const Vec6 a = link_jdot_v(r, data, link, p_L);
    EXPECT_LT((a - fd).norm(), 1e-5 * (1 + fd.norm())) << a.transpose() << "\nvs\n" << fd.transpose();
  }
}

void check_dynamics(const RobotModel& r, int seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  VecX q, v;
  random_state(r, rng, q, v);
  q[2] += 5;  // well above the floor: no contacts
  RobotData data(r);
  update_dynamics(r, data, q, v);
  const MatX M = mass_matrix(r, data);
  const VecX bias = bias_forces(r, data);
  ASSERT_EQ(M.rows(), r.nv());
  EXPECT_LT((M - M.transpose()).norm(), 1e-12 * M.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(M).eigenvalues().minCoeff(), 0);

  // Equations of motion: M q̈ + c = τ_applied + τ_actuator + τ_passive + τ_constraint, with
  // q̈ from MuJoCo's own forward dynamics on another mjData.
  RobotData sim(r);
  mjData* d = sim.mj();
  mju_copy(d->qpos, q.data(), r.nq());
  mju_copy(d->qvel, v.data(), r.nv());
  std::normal_distribution<double> n(0, 5);
  for (int i = 0; i < r.nv(); ++i) d->qfrc_applied[i] = n(rng);
  for (int k = 0; k < r.nu(); ++k) d->ctrl[k] = n(rng);
  mj_forward(r.mj(), d);
  EXPECT_EQ(d->ncon, 0);
  const VecX qacc = Eigen::Map<const VecX>(d->qacc, r.nv());
  VecX forces = VecX::Zero(r.nv());
  for (const mjtNum* f : {d->qfrc_applied, d->qfrc_actuator, d->qfrc_passive, d->qfrc_constraint})
    forces += Eigen::Map<const VecX>(f, r.nv());
  EXPECT_LT((M * qacc + bias - forces).norm(), 1e-8 * (1 + forces.norm()));
}

void check_integrate_difference(const RobotModel& r, int seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  VecX q, v;
  random_state(r, rng, q, v);
  const double dt = 0.01;
  const VecX q2 = integrate(r, q, v, dt);
  EXPECT_NEAR(q2.segment<4>(3).norm(), 1.0, 1e-12);
  EXPECT_LT((difference(r, q, q2, dt) - v).norm(), 1e-9);
  // Joints integrate linearly.
  EXPECT_LT((q2.tail(r.nu()) - q.tail(r.nu()) - dt * v.tail(r.nu())).norm(), 1e-12);
  // Root linear velocity is in the world frame.
  EXPECT_LT((q2.head<3>() - q.head<3>() - dt * v.head<3>()).norm(), 1e-12);
}

const RobotModel& mini() {
  static const std::unique_ptr<RobotModel> model =
      RobotModel::load(test::source_path("tests/data/urdf/mini_biped/robot.yaml"));
  return *model;
}

TEST(Kinematics, JacobiansMatchFiniteDifferencesOnTheTestRobot) {
  for (int seed = 1; seed <= 3; ++seed) check_jacobians(mini(), seed);
}

TEST(Kinematics, JdotVMatchesFiniteDifferencesOnTheTestRobot) {
  for (int seed = 1; seed <= 3; ++seed) check_jdot_v(mini(), seed);
}

TEST(Kinematics, MassMatrixAndBiasSatisfyTheEquationsOfMotion) {
  for (int seed = 1; seed <= 3; ++seed) check_dynamics(mini(), seed);
}

TEST(Kinematics, IntegrateDifferenceRoundTrip) {
  for (int seed = 1; seed <= 5; ++seed) check_integrate_difference(mini(), seed);
}

TEST(Kinematics, LinkPoseOfMergedLinks) {
  const RobotModel& r = mini();
  RobotData data(r);
  VecX q, v;
  std::mt19937 rng(7);
  random_state(r, rng, q, v);
  update_kinematics(r, data, q);
  for (const Joint& j : r.joints()) {
    if (j.type != JointType::Fixed) continue;
    const Iso3 expected = link_pose(r, data, j.parent_link) * j.X_P_J;
    EXPECT_TRUE(link_pose(r, data, j.child_link).isApprox(expected, 1e-12)) << j.name;
  }
  // The root link's pose is the free joint's configuration.
  const Iso3 X = link_pose(r, data, r.root_link());
  EXPECT_TRUE(X.translation().isApprox(q.head<3>()));
  EXPECT_TRUE(Quat(X.linear()).isApprox(Quat(q[3], q[4], q[5], q[6])) ||
              Quat(X.linear()).coeffs().isApprox(-Quat(q[3], q[4], q[5], q[6]).coeffs()));
}

TEST(Kinematics, RealRobotsMatchFiniteDifferences) {
  RT_REQUIRE_SHARED(robots, "robots");
  for (const char* name : {"g1", "h1", "jvrc1"}) {
    SCOPED_TRACE(name);
    const RobotModel* r = &test::cached_robot(name);
    check_jacobians(*r, 11);
    check_jdot_v(*r, 12);
    check_dynamics(*r, 13);
    check_integrate_difference(*r, 14);
  }
}

}  // namespace
}  // namespace rt
