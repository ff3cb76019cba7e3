#include "retarget/balance/com_replanner.hpp"

#include <gtest/gtest.h>

namespace rt {
namespace {

ClosedLoopModel model_5ms() { return BalanceController(PendulumModel{0.70, 9.81}).closed_loop_model(0.005); }

Mat42 rest(const Vec2& c) {
  Mat42 x = Mat42::Zero();
  x.row(0) = c.transpose();
  x.row(1) = c.transpose();
  return x;
}

TEST(CopPredictor, RecursionMatchesEquation27) {
  const ClosedLoopModel m = model_5ms();
  const CopPredictor p(m, 50);
  Mat42 x0;
  x0 << 0.01, -0.02, 0.03, 0.0, 0.1, 0.05, -0.2, 0.3;
  Mat2X U(2, 50);
  for (int k = 0; k < 50; ++k) U.col(k) = Vec2(0.05 * std::sin(0.1 * k), 0.02 * k / 50.0);
  Mat2X y(2, 50);
  p.predict(x0, U, 50, y);
  for (int n : {1, 7, 50}) {
    // Direct eq. (27) with explicit matrix powers.
    Mat4 An = Mat4::Identity();
    for (int i = 0; i < n; ++i) An = m.A * An;
    Vec2 direct = (m.C * An * x0).transpose();
    for (int k = 0; k < n; ++k) {
      Mat4 Ap = Mat4::Identity();
      for (int i = 0; i < n - 1 - k; ++i) Ap = m.A * Ap;
      direct += (m.C * Ap * m.B)(0, 0) * U.col(k);
    }
    EXPECT_TRUE(direct.isApprox(y.col(n - 1), 1e-12)) << n;
    EXPECT_TRUE(direct.isApprox(p.predict_at(x0, U, n), 1e-12)) << n;
  }
}

TEST(ComReplanner, ClosedFormMatchesDenseSolve) {
  const ClosedLoopModel m = model_5ms();
  ComReplanOptions o;
  o.horizon = 40;
  const ComReplanner planner(m, o);
  const Mat42 x0 = rest(Vec2(0, 0));
  Mat2X U = Mat2X::Zero(2, 40);
  const int n = 30;
  const Vec2 y_ref(0.02, 0.08);
  Mat2X U_fast = U;
  const Vec2 y_after = planner.solve(x0, U_fast, n, y_ref);

  // Dense: minimise ½|ŷ + mᵀδ − y_ref|² + ½δᵀWδ per axis.
  VecX mvec(n);
  for (int k = 0; k < n; ++k) mvec[k] = planner.predictor().impulse(n - 1 - k);
  MatX W = MatX::Zero(n, n);
  for (int i = 0; i < n; ++i) W(i, i) = o.w * (i + 1.0) * (i + 1.0);
  const Vec2 y_hat = planner.predictor().predict_at(x0, U, n);
  for (int axis = 0; axis < 2; ++axis) {
    const VecX delta = (W + mvec * mvec.transpose()).ldlt().solve(-mvec * (y_hat[axis] - y_ref[axis]));
    EXPECT_TRUE(delta.isApprox(U_fast.row(axis).head(n).transpose(), 1e-9));
  }
  EXPECT_TRUE(y_after.isApprox(planner.predictor().predict_at(x0, U_fast, n), 1e-12));
  // The change moves ŷ_n towards y_ref and leaves the inputs after n untouched.
  EXPECT_LT((y_after - y_ref).norm(), (y_hat - y_ref).norm());
  EXPECT_TRUE(U_fast.rightCols(40 - n).isZero());
}

// Paper §VII-A in the model: both feet down, the right foot lifts for t in [1, 2) s. Without
// re-planning the COP stays between the feet; with it the COM reference moves about 0.5 s before the
// lift, the COP first moves towards the right foot and reaches the left sole before t = 1 s.
TEST(ComReplanner, FootLiftInTheModelReproducesFig7) {
  const ClosedLoopModel m = model_5ms();
  const ComReplanOptions o;  // paper defaults: N = 100, h_max = 0.8, w = 0.01
  const ComReplanner planner(m, o);
  const double dt = o.period_s, half_width = 0.05, half_length = 0.1, foot_y = 0.1;
  auto sole = [&](double yc) {
    return std::vector<Vec2>{{-half_length, yc - half_width}, {half_length, yc - half_width},
                             {half_length, yc + half_width}, {-half_length, yc + half_width}};
  };
  SupportFrame both, left_only;
  std::vector<Vec2> all = sole(foot_y);
  for (const Vec2& v : sole(-foot_y)) all.push_back(v);
  both.polygon = SupportPolygon::convex_hull(all);
  both.sole_center_W = {Vec2(0, foot_y), Vec2(0, -foot_y)};
  left_only = both;
  left_only.polygon = SupportPolygon::convex_hull(sole(foot_y));
  left_only.contact = {true, false};

  const int steps = static_cast<int>(3.0 / dt);
  auto support_at = [&](int k) -> const SupportFrame& {
    const double t = k * dt;
    return (t >= 1.0 && t < 2.0) ? left_only : both;
  };
  Mat2X c_ref = Mat2X::Zero(2, steps + o.horizon + 1);  // the original reference: COM stays centred
  Mat42 x = rest(Vec2::Zero());
  std::vector<double> cop_y, com_y;
  double first_shift = 0;
  double first_activation_t = -1, min_cop_y = 0;
  for (int k = 0; k < steps; ++k) {
    auto window = c_ref.middleCols(k, o.horizon);
    const auto event = planner.step(x, window, [&](int j) -> const SupportFrame& { return support_at(k + j); });
    if (event && first_activation_t < 0) {
      first_activation_t = k * dt;
      first_shift = event->max_shift_m;
      EXPECT_EQ(event->kind, 1);
    }
    x = m.A * x + m.B * c_ref.col(k).transpose();
    cop_y.push_back((m.C * x)(0, 1));
    com_y.push_back(x(0, 1));
    if (k * dt < 1.0) min_cop_y = std::min(min_cop_y, cop_y.back());
  }
  // Activation when the lift enters the 0.5 s window.
  EXPECT_NEAR(first_activation_t, 0.5, 0.02);
  // The COP first moves towards the right foot (negative y) ...
  EXPECT_LT(min_cop_y, -0.01);
  // ... and is on the left sole before the lift.
  const int k_lift = static_cast<int>(1.0 / dt) - 1;
  EXPECT_TRUE(left_only.polygon.contains(Vec2(0, cop_y[static_cast<std::size_t>(k_lift)])))
      << "COP y at t=1s: " << cop_y[static_cast<std::size_t>(k_lift)];
  // The COP stays on the left sole during the whole lift.
  for (int k = k_lift + 1; k < static_cast<int>(2.0 / dt); ++k)
    EXPECT_TRUE(left_only.polygon.contains(Vec2(0, cop_y[static_cast<std::size_t>(k)]), -0.005)) << k * dt;
  // The reference moved towards the left foot at the first activation, and the model's COM follows it
  // onto the left sole without going beyond it.
  EXPECT_GT(first_shift, 0.05);
  EXPECT_GT(com_y[static_cast<std::size_t>(1.5 / dt)], foot_y - half_width);
  EXPECT_LT(*std::max_element(com_y.begin(), com_y.end()), foot_y + half_width);
}

}  // namespace
}  // namespace rt
