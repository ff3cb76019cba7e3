// The sparse interior-point QP against the dense active-set solver, and the whole-clip COM plan on
// synthetic footsteps: a standing reference is left alone, a COM held outside the stance foot is
// moved so that its ZMP lies inside, and a walk's ZMP follows the feet.
#include "retarget/balance/zmp_plan.hpp"

#include <gtest/gtest.h>

#include <random>

#include "retarget/control/dense_qp.hpp"

namespace rt {
namespace {

SupportPolygon rectangle(const Vec2& centre, double length, double width) {
  std::vector<Vec2> corners;
  for (double sx : {-0.5, 0.5})
    for (double sy : {-0.5, 0.5}) corners.push_back(centre + Vec2(sx * length, sy * width));
  return SupportPolygon::convex_hull(corners);
}

// With a large penalty the soft-constrained minimiser approaches the hard one (the violation is
// the constraint force over the penalty).
TEST(SparseQp, ApproachesTheDenseActiveSetSolution) {
  std::mt19937 rng(11);
  std::normal_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 12, m = 30;
    MatX L(n, n), C(m, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) L(i, j) = u(rng);
    const MatX Hd = L * L.transpose() + 0.1 * MatX::Identity(n, n);
    VecX g(n), d(m);
    for (int i = 0; i < n; ++i) g[i] = 3 * u(rng);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < n; ++j) C(i, j) = u(rng);
      d[i] = -1 - std::abs(u(rng));  // C x ≥ d holds at x = 0: feasible
    }
    DenseQp dense;
    VecX x_dense;
    ASSERT_EQ(dense.solve(Hd, g, C, d, x_dense), QpStatus::Solved);
    // Ax ≤ b with A = −C, b = −d.
    const SparseMat H = Hd.sparseView(), A = MatX(-C).sparseView();
    VecX x;
    SparseQpOptions o;
    o.penalty = 1e8;
    const SparseQpResult r = solve_sparse_qp(H, g, A, -d, x, o);
    ASSERT_EQ(r.status, SparseQpStatus::Solved) << "trial " << trial;
    EXPECT_LT((x - x_dense).cwiseAbs().maxCoeff(), 1e-5) << "trial " << trial;
    EXPECT_LT(r.max_violation, 1e-6);
    // A smaller penalty violates more, never less.
    o.penalty = 1e2;
    VecX x_soft;
    const SparseQpResult soft = solve_sparse_qp(H, g, A, -d, x_soft, o);
    ASSERT_EQ(soft.status, SparseQpStatus::Solved);
    EXPECT_GE(soft.max_violation, r.max_violation);
  }
}

TEST(ZmpPlan, LeavesAStandingReferenceAlone) {
  const SupportPolygon feet = SupportPolygon::convex_hull(
      {Vec2(-0.1, -0.15), Vec2(0.1, -0.15), Vec2(0.1, 0.15), Vec2(-0.1, 0.15)});
  std::vector<ZmpPlanSample> samples(300);
  for (ZmpPlanSample& s : samples) {
    s.com_ref_W = Vec2(0.01, -0.02);
    s.zmp_gain_s2 = 0.7 / 9.81;
    s.support = feet.half_planes(0.015);
  }
  const ZmpPlan plan = plan_com_zmp(samples);
  ASSERT_EQ(plan.solver.status, SparseQpStatus::Solved);
  EXPECT_LT(plan.max_shift_m, 1e-3);
  EXPECT_EQ(plan.violated_samples, 0);
}

// Double support, then 1 s on the left foot with the reference COM held 10 cm to the right of it
// (between the feet, where it was), then double support again: the plan must bring the COM (and
// its ZMP) over the left sole.
TEST(ZmpPlan, MovesACentredComOverTheStanceFoot) {
  const double h = 0.7 / 9.81;
  const SupportPolygon left = rectangle(Vec2(0, 0.1), 0.2, 0.1), right = rectangle(Vec2(0, -0.1), 0.2, 0.1);
  std::vector<Vec2> both_corners = left.vertices();
  both_corners.insert(both_corners.end(), right.vertices().begin(), right.vertices().end());
  const SupportPolygon both = SupportPolygon::convex_hull(both_corners);
  std::vector<ZmpPlanSample> samples(300);
  for (int k = 0; k < 300; ++k) {
    ZmpPlanSample& s = samples[static_cast<std::size_t>(k)];
    s.com_ref_W = Vec2(0, 0);
    s.zmp_gain_s2 = h;
    const bool single = k >= 100 && k < 200;
    s.support = (single ? left : both).half_planes(0.015);
  }
  const ZmpPlan plan = plan_com_zmp(samples);
  ASSERT_EQ(plan.solver.status, SparseQpStatus::Solved);
  for (int k = 100; k < 200; ++k) {
    EXPECT_LE(left.signed_distance(plan.zmp_W.col(k)), -0.015 + 1e-4) << "sample " << k;
  }
  EXPECT_LT(plan.max_violation_m, 1e-4);
  // The COM swings towards the left sole (y in [0.05, 0.15]): it may stay short of it, moving
  // dynamically, but not where the reference held it.
  EXPECT_GT(plan.com_W(1, 150), 0.03);
  EXPECT_GE(plan.max_shift_m, plan.com_W.col(150).norm() - 1e-12);
  // Rest at both ends: the first and last three samples coincide.
  EXPECT_EQ(plan.com_W.col(0), plan.com_W.col(2));
  EXPECT_EQ(plan.com_W.col(297), plan.com_W.col(299));
}

// A ZMP offset (the multibody correction) moves the plan by the same amount where it binds.
TEST(ZmpPlan, HonoursTheMultibodyOffset) {
  const SupportPolygon foot = rectangle(Vec2(0, 0), 0.2, 0.1);
  std::vector<ZmpPlanSample> samples(200);
  for (ZmpPlanSample& s : samples) {
    s.com_ref_W = Vec2(0, 0.08);  // outside the sole
    s.zmp_gain_s2 = 0.07;
    s.zmp_offset_W = Vec2(0, 0.02);
    s.support = foot.half_planes(0.0);
  }
  const ZmpPlan plan = plan_com_zmp(samples);
  ASSERT_EQ(plan.solver.status, SparseQpStatus::Solved);
  EXPECT_NEAR(plan.com_W(1, 100), 0.05 - 0.02, 2e-4);  // p = c + 0.02 must reach y ≤ 0.05
  EXPECT_NEAR(plan.zmp_W(1, 100), 0.05, 2e-4);
}

}  // namespace
}  // namespace rt
