#include "retarget/ik/bounded_lm.hpp"

#include <gtest/gtest.h>

namespace rt {
namespace {

LeastSquaresProblem euclidean(int n, std::function<void(const VecX&, VecX&, MatX*)> f, const VecX& lo, const VecX& hi) {
  LeastSquaresProblem p;
  p.tangent_size = n;
  p.evaluate = [f](const VecX& x, MatX* H, VecX* g) {
    VecX r;
    MatX J;
    f(x, r, H ? &J : nullptr);
    if (H) {
      *H = J.transpose() * J;
      *g = J.transpose() * r;
    }
    return 0.5 * r.squaredNorm();
  };
  p.retract = [](const VecX& x, const VecX& d) { return (x + d).eval(); };
  p.step_bounds = [lo, hi](const VecX& x, VecX& l, VecX& u) {
    l = lo - x;
    u = hi - x;
  };
  return p;
}

TEST(BoundedLm, RosenbrockUnconstrained) {
  const auto f = [](const VecX& x, VecX& r, MatX* J) {
    r.resize(2);
    r << 10 * (x[1] - x[0] * x[0]), 1 - x[0];
    if (J) {
      J->resize(2, 2);
      *J << -20 * x[0], 10, -1, 0;
    }
  };
  VecX x(2);
  x << -1.2, 1;
  BoundedLmOptions o;
  o.max_iterations = 200;
  const auto res = solve_bounded_lm(euclidean(2, f, VecX::Constant(2, -1e9), VecX::Constant(2, 1e9)), x, o);
  EXPECT_NEAR(x[0], 1, 1e-6);
  EXPECT_NEAR(x[1], 1, 1e-6);
  EXPECT_LT(res.cost, 1e-12);
}

TEST(BoundedLm, ActiveBoundIsFrozenAndOptimalOnTheFace) {
  // min ½|x − c|² with c outside the box: the solution is the projection, reached exactly.
  const Vec3 c(2.0, -3.0, 0.5);
  const auto f = [c](const VecX& x, VecX& r, MatX* J) {
    r = x - c;
    if (J) *J = MatX::Identity(3, 3);
  };
  VecX x = VecX::Zero(3);
  const VecX lo = VecX::Constant(3, -1), hi = VecX::Constant(3, 1);
  const auto res = solve_bounded_lm(euclidean(3, f, lo, hi), x);
  EXPECT_TRUE(x.isApprox(Vec3(1, -1, 0.5), 1e-6)) << x.transpose();
  EXPECT_EQ(res.active_bounds, 2);
  EXPECT_TRUE(res.converged);
}

TEST(BoundedLm, NeverIncreasesCost) {
  // A residual whose Jacobian is wrong in sign: LM must refuse every step, not diverge.
  const auto f = [](const VecX& x, VecX& r, MatX* J) {
    r = x;
    if (J) *J = -MatX::Identity(2, 2);
  };
  VecX x(2);
  x << 0.3, -0.2;
  const auto res = solve_bounded_lm(euclidean(2, f, VecX::Constant(2, -1), VecX::Constant(2, 1)), x);
  EXPECT_LE(res.cost, res.initial_cost);
}

}  // namespace
}  // namespace rt
