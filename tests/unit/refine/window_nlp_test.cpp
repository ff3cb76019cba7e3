// The window NLP's derivatives and sparsity structures against finite differences on a small window
// (humanoid25, 14 frames at 60 Hz with stride 2: 10 control points x 31 coordinates).

#include "src/refine/window_nlp.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "retarget/core/error.hpp"
#include "small_window.hpp"

namespace rt::refine {
namespace {

using test::SmallWindow;
using test::build;
using test::perturbed_point;

MatX dense(int rows, int cols, const std::vector<int>& r, const std::vector<int>& c, const VecX& v) {
  MatX M = MatX::Zero(rows, cols);
  for (std::size_t e = 0; e < r.size(); ++e) M(r[e], c[e]) += v[static_cast<Eigen::Index>(e)];
  return M;
}

void expect_unique(const std::vector<int>& r, const std::vector<int>& c) {
  std::set<std::pair<int, int>> seen;
  for (std::size_t e = 0; e < r.size(); ++e) EXPECT_TRUE(seen.insert({r[e], c[e]}).second) << "duplicate entry " << r[e] << "," << c[e];
}

// Gradient, constraint Jacobian and Gauss–Newton Hessian against central differences; every
// nonzero found by finite differences must be inside the declared structures.
void check_derivatives(SmallWindow& w) {
  WindowNlp nlp(w.robot, w.data, w.spec, w.weights);
  const int n = nlp.num_variables(), m = nlp.num_constraints();
  ASSERT_GT(n, 0);
  expect_unique(nlp.jac_rows(), nlp.jac_cols());
  expect_unique(nlp.hess_rows(), nlp.hess_cols());
  for (std::size_t e = 0; e < nlp.hess_rows().size(); ++e) EXPECT_GE(nlp.hess_rows()[e], nlp.hess_cols()[e]);

  VecX x = perturbed_point(nlp);
  nlp.evaluate(x.data());
  const VecX grad = nlp.gradient();
  const MatX J = dense(m, n, nlp.jac_rows(), nlp.jac_cols(), nlp.jac_values());
  VecX H_values(static_cast<Eigen::Index>(nlp.hess_rows().size()));
  const VecX zero_lambda = VecX::Zero(m);
  nlp.lagrangian_hessian(1.0, zero_lambda.data(), H_values.data());
  MatX H = dense(n, n, nlp.hess_rows(), nlp.hess_cols(), H_values);
  H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
  const VecX r0 = nlp.residuals(x.data());
  EXPECT_NEAR(0.5 * r0.squaredNorm(), nlp.objective(), 1e-12 * std::max(1.0, nlp.objective()));

  const double h = 1e-6;
  VecX fd_grad(n);
  MatX fd_J(m, n), fd_Jr(r0.size(), n);
  for (int i = 0; i < n; ++i) {
    VecX xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    nlp.evaluate(xp.data());
    const double fp = nlp.objective();
    const VecX gp = nlp.constraints();
    nlp.evaluate(xm.data());
    fd_grad[i] = (fp - nlp.objective()) / (2 * h);
    fd_J.col(i) = (gp - nlp.constraints()) / (2 * h);
    fd_Jr.col(i) = (nlp.residuals(xp.data()) - nlp.residuals(xm.data())) / (2 * h);
  }
  EXPECT_LT((grad - fd_grad).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, grad.cwiseAbs().maxCoeff()));
  EXPECT_LT((J - fd_J).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, J.cwiseAbs().maxCoeff()));
  const MatX H_gn = fd_Jr.transpose() * fd_Jr;
  EXPECT_LT((H - H_gn).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, H_gn.cwiseAbs().maxCoeff()));
  // Structures: finite-difference nonzeros outside them would mean missing entries.
  const MatX J_pattern = dense(m, n, nlp.jac_rows(), nlp.jac_cols(), VecX::Ones(static_cast<Eigen::Index>(nlp.jac_rows().size())));
  MatX H_pattern = dense(n, n, nlp.hess_rows(), nlp.hess_cols(), VecX::Ones(static_cast<Eigen::Index>(nlp.hess_rows().size())));
  H_pattern.triangularView<Eigen::StrictlyUpper>() = H_pattern.transpose();
  int outside = 0;
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < n; ++k) outside += J_pattern(i, k) == 0 && std::abs(fd_J(i, k)) > 1e-8;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) outside += H_pattern(i, k) == 0 && std::abs(H_gn(i, k)) > 1e-8;
  EXPECT_EQ(outside, 0);
}

TEST(WindowNlp, DerivativesMatchFiniteDifferences) {
  SmallWindow w;
  build(w, 0, true);
  check_derivatives(w);
}

TEST(WindowNlp, DerivativesWithPinnedControlPoints) {
  SmallWindow w;
  build(w, 3, true);
  check_derivatives(w);
}

TEST(WindowNlp, DerivativesOfEachStage) {
  const RobotModel& model = test::robot("humanoid25");
  const NlpRobot robot(model, 1e-4);
  std::vector<std::uint8_t> feet = robot.moves_feet, other(robot.moves_feet.size());
  for (std::size_t i = 0; i < other.size(); ++i) other[i] = !feet[i];
  SmallWindow a, b;
  build(a, 1, true, feet);
  check_derivatives(a);
  build(b, 1, false, other);
  check_derivatives(b);
}

// The constraint part of the Lagrangian Hessian (unprojected) against finite differences of Jᵀλ.
TEST(WindowNlp, ConstraintCurvatureMatchesFiniteDifferences) {
  SmallWindow w;
  build(w, 1, false);  // still rows carry no curvature: leave them out here
  WindowNlp nlp(w.robot, w.data, w.spec, w.weights);
  const int n = nlp.num_variables(), m = nlp.num_constraints();
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX lambda(m);
  for (int i = 0; i < m; ++i) lambda[i] = u(rng);
  const VecX x = perturbed_point(nlp);
  nlp.evaluate(x.data());
  VecX values(static_cast<Eigen::Index>(nlp.hess_rows().size()));
  nlp.lagrangian_hessian(0.0, lambda.data(), values.data(), false);
  MatX H = dense(n, n, nlp.hess_rows(), nlp.hess_cols(), values);
  H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
  const double h = 1e-6;
  MatX fd(n, n);
  for (int i = 0; i < n; ++i) {
    VecX xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    nlp.evaluate(xp.data());
    const VecX gp = dense(m, n, nlp.jac_rows(), nlp.jac_cols(), nlp.jac_values()).transpose() * lambda;
    nlp.evaluate(xm.data());
    fd.col(i) = (gp - dense(m, n, nlp.jac_rows(), nlp.jac_cols(), nlp.jac_values()).transpose() * lambda) / (2 * h);
  }
  EXPECT_GT(fd.cwiseAbs().maxCoeff(), 1e-3);  // the curvature is there
  EXPECT_LT((H - fd).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, fd.cwiseAbs().maxCoeff()));

  // The projected (default) version is positive semidefinite on top of the Gauss–Newton part.
  nlp.lagrangian_hessian(1.0, lambda.data(), values.data());
  MatX Hp = dense(n, n, nlp.hess_rows(), nlp.hess_cols(), values);
  Hp.triangularView<Eigen::StrictlyUpper>() = Hp.transpose();
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(Hp).eigenvalues().minCoeff(), -1e-9);
}

TEST(WindowNlp, VelocityRowsAreAnActiveSet) {
  SmallWindow all, none;
  build(all, 0, false);
  build(none, 0, false);
  none.weights.velocity_activation = 1e9;  // no row from the initial guess
  WindowNlp a(all.robot, all.data, all.spec, all.weights), b(none.robot, none.data, none.spec, none.weights);
  EXPECT_GT(a.num_velocity_rows(), 0);
  EXPECT_EQ(b.num_velocity_rows(), 0);
  // Controls that exceed one joint's bound between two control points: reported, then forced in.
  MatX C = none.spec.controls;
  const int joint = 6 + 3;
  C(joint, 5) = C(joint, 4) + 1.0;  // 1 rad in 1/30 s: far above any URDF limit
  const std::vector<int> violated = b.velocity_rows_above(C, 1.0 + 1e-9);
  ASSERT_FALSE(violated.empty());
  EXPECT_NE(std::find(violated.begin(), violated.end(), 4 * all.model.nv() + joint), violated.end());
  none.spec.forced_velocity_rows.assign(static_cast<std::size_t>(C.cols() * all.model.nv()), 0);
  for (int v : violated) none.spec.forced_velocity_rows[static_cast<std::size_t>(v)] = 1;
  WindowNlp c(none.robot, none.data, none.spec, none.weights);
  EXPECT_EQ(c.num_velocity_rows(), static_cast<int>(violated.size()));
  EXPECT_GE(b.velocity_rows_above(C, 0.0).size(), violated.size());
}

TEST(WindowNlp, RejectsInconsistentSpecs) {
  SmallWindow w;
  build(w, 0, false);
  WindowSpec bad = w.spec;
  bad.num_pinned = static_cast<int>(bad.controls.cols());
  EXPECT_THROW(WindowNlp(w.robot, w.data, bad, w.weights), InternalError);
  bad = w.spec;
  bad.points.front().support.index[0] = -5;
  EXPECT_THROW(WindowNlp(w.robot, w.data, bad, w.weights), InternalError);
  bad = w.spec;
  bad.free_coordinates.assign(bad.controls.rows(), 0);
  EXPECT_THROW(WindowNlp(w.robot, w.data, bad, w.weights), InternalError);
}

}  // namespace
}  // namespace rt::refine
