// Kinematics/dynamics API over MuJoCo, checked against finite differences in random moving states
// (on the test robot always, and on the real robots when the shared data is present).

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
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

// J̇·v against MuJoCo's own acceleration pass (mj_rnePostConstraint with q̈ = 0, at each body's
// centre of mass), and the dof chains against the sparsity of MuJoCo's Jacobians.
void check_jdot_v_and_chains(const RobotModel& r, int seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  RobotData data(r);
  VecX q, v;
  random_state(r, rng, q, v);
  update_dynamics(r, data, q, v);
  RobotData reference(r);
  update_dynamics(r, reference, q, v);
  mjData* d = reference.mj();
  mju_zero(d->qacc, r.nv());
  mj_rnePostConstraint(r.mj(), d);
  for (int link = 0; link < static_cast<int>(r.links().size()); ++link) {
    SCOPED_TRACE(r.links()[static_cast<std::size_t>(link)].name);
    const Link& l = r.links()[static_cast<std::size_t>(link)];
    if (l.body == 0) continue;  // a link welded to the world (a URDF "world" link) does not move
    mjtNum acc[6];
    mj_objectAcceleration(r.mj(), d, mjOBJ_BODY, l.body, acc, 0);
    // MuJoCo reports a body's acceleration at its centre of mass: the same point in link coordinates.
    const Vec3 p_L = link_pose(r, data, link).inverse() * Eigen::Map<const Vec3>(d->xipos + 3 * l.body);
    const Vec6 a = link_jdot_v(r, data, link, p_L);
    const Vec3 lin = Vec3(acc[3], acc[4], acc[5]) + Eigen::Map<const Vec3>(r.mj()->opt.gravity);
    EXPECT_LT((a.head<3>() - lin).norm(), 1e-9 * (1 + lin.norm()));
    EXPECT_LT((a.tail<3>() - Vec3(acc[0], acc[1], acc[2])).norm(), 1e-9 * (1 + a.tail<3>().norm()));

    const MatX J = link_jacobian(r, data, link);
    const std::vector<int> chain = link_dof_chain(r, link);
    EXPECT_TRUE(std::is_sorted(chain.begin(), chain.end()));
    std::vector<bool> in_chain(static_cast<std::size_t>(r.nv()), false);
    for (int j : chain) in_chain[static_cast<std::size_t>(j)] = true;
    for (int j = 0; j < r.nv(); ++j) {
      if (!in_chain[static_cast<std::size_t>(j)]) {
        EXPECT_EQ(J.col(j).norm(), 0.0) << "dof " << j;
      }
    }
    // The root's six dofs move every link of a floating robot.
    EXPECT_GE(chain.size(), 6u);
  }
}

// The row-wise sparse solve against MuJoCo's mj_solveM and the dense mass matrix.
void check_solve_mass_matrix(const RobotModel& r, int seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  RobotData data(r);
  VecX q, v;
  random_state(r, rng, q, v);
  update_dynamics(r, data, q, v);
  const int nv = r.nv(), n = 41;
  std::normal_distribution<double> g(0, 1);
  MatX B(nv, n);
  for (int i = 0; i < B.size(); ++i) B.data()[i] = g(rng);
  MatXr X = B;
  solve_mass_matrix(r, data, X);
  MatX expected(nv, n);  // column-major: one right-hand side per column for mj_solveM
  mj_solveM(r.mj(), data.mj(), expected.data(), B.data(), n);
  EXPECT_LT((X - expected).norm(), 1e-12 * (1 + expected.norm()));
  EXPECT_LT((mass_matrix(r, data) * X - B).norm(), 1e-9 * (1 + B.norm()));
}

// assign_dynamics from MuJoCo's own step stages gives the controller exactly what update_dynamics
// computes: every query answers bit for bit the same.
void check_assign_dynamics(const RobotModel& r, int seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  VecX q, v;
  random_state(r, rng, q, v);
  RobotData sim(r), assigned(r), updated(r);
  mju_copy(sim.mj()->qpos, q.data(), r.nq());
  mju_copy(sim.mj()->qvel, v.data(), r.nv());
  mj_step1(r.mj(), sim.mj());
  assign_dynamics(r, assigned, *sim.mj());
  update_dynamics(r, updated, q, v);
  EXPECT_EQ(mass_matrix(r, assigned), mass_matrix(r, updated));
  EXPECT_EQ(bias_forces(r, assigned), bias_forces(r, updated));
  EXPECT_EQ(com_position(r, assigned), com_position(r, updated));
  EXPECT_EQ(com_jacobian(r, assigned), com_jacobian(r, updated));
  for (int link = 0; link < static_cast<int>(r.links().size()); ++link) {
    SCOPED_TRACE(r.links()[static_cast<std::size_t>(link)].name);
    EXPECT_EQ(link_pose(r, assigned, link).matrix(), link_pose(r, updated, link).matrix());
    EXPECT_EQ(link_jacobian(r, assigned, link), link_jacobian(r, updated, link));
    EXPECT_EQ(link_jdot_v(r, assigned, link), link_jdot_v(r, updated, link));
  }
  for (int foot = 0; foot < 2; ++foot) EXPECT_EQ(lowest_sole_corner_z(r, assigned, foot), lowest_sole_corner_z(r, updated, foot));
  MatXr X1 = MatXr::Identity(r.nv(), r.nv()), X2 = X1;
  solve_mass_matrix(r, assigned, X1);
  solve_mass_matrix(r, updated, X2);
  EXPECT_EQ(X1, X2);
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

TEST(Kinematics, JdotVAndDofChainsMatchMujocoOnTheTestRobot) {
  for (int seed = 1; seed <= 3; ++seed) check_jdot_v_and_chains(mini(), seed);
}

TEST(Kinematics, SparseMassMatrixSolveMatchesMujoco) {
  for (int seed = 1; seed <= 3; ++seed) check_solve_mass_matrix(mini(), seed);
  check_solve_mass_matrix(test::cached_robot("humanoid25"), 4);
}

TEST(Kinematics, AssignDynamicsFromMujocoStepStagesEqualsUpdateDynamics) {
  for (int seed = 1; seed <= 3; ++seed) check_assign_dynamics(mini(), seed);
  check_assign_dynamics(test::cached_robot("humanoid25"), 4);
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
    check_jdot_v_and_chains(*r, 15);
    check_solve_mass_matrix(*r, 16);
    check_assign_dynamics(*r, 17);
    check_dynamics(*r, 13);
    check_integrate_difference(*r, 14);
  }
}

}  // namespace
}  // namespace rt
