#include "retarget/balance/balance_controller.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "retarget/core/error.hpp"

namespace rt {
namespace {

BalanceController make_controller() { return BalanceController(PendulumModel{0.70, 9.81}); }

TEST(BalanceController, ClosedLoopAndObserverAreStable) {
  const BalanceController bc = make_controller();
  for (const Mat4& M : {bc.A_cl(), bc.A_b()}) {
    const Eigen::Vector4cd ev = M.eigenvalues();
    for (int i = 0; i < 4; ++i) EXPECT_LT(ev[i].real(), -0.1) << M;
  }
  const ClosedLoopModel d = bc.closed_loop_model(0.005);
  const Eigen::Vector4cd ev = d.A.eigenvalues();
  for (int i = 0; i < 4; ++i) EXPECT_LT(std::abs(ev[i]), 1.0);
}

// Simulates the true pendulum driven by the controller's desired COP (the tracking controller is
// assumed to realise it after a first-order lag), with measurements fed back to the observer.
struct Trace {
  std::vector<double> t, com, cop;
};

Trace simulate_step(const BalanceController& bc, double c_ref, double duration_s) {
  const double dt = bc.options().control_period_s;
  const double w2 = bc.model().omega_sq();
  BalanceState est = bc.rest_state(Vec2::Zero());
  double c = 0, cd = 0, p = 0;
  Trace tr;
  for (double t = 0; t < duration_s; t += dt) {
    const Vec2 p_des = bc.step(est, Vec2(c_ref, 0), Vec2(c, 0), Vec2(p, 0));
    p += (p_des.x() - p) * std::min(1.0, dt / 0.01);  // 10 ms COP tracking lag
    for (int k = 0; k < 10; ++k) {  // integrate the plant at dt/10
      cd += w2 * (c - p) * dt / 10;
      c += cd * dt / 10;
    }
    tr.t.push_back(t);
    tr.com.push_back(c);
    tr.cop.push_back(p);
  }
  return tr;
}

TEST(BalanceController, StepMakesCopMoveAwayFirstThenSettleOnReference) {
  const BalanceController bc = make_controller();
  const double target = 0.05;
  const Trace tr = simulate_step(bc, target, 6.0);
  // Non-minimum phase (paper Fig. 7): to accelerate the COM towards +x, the COP first goes to −x.
  const double min_cop = *std::min_element(tr.cop.begin(), tr.cop.begin() + 200);
  EXPECT_LT(min_cop, -0.005);
  // ... then it moves towards the target and overshoots past the COM to decelerate it.
  const double max_cop = *std::max_element(tr.cop.begin(), tr.cop.end());
  EXPECT_GT(max_cop, target);
  // Steady state: COP = COM = reference.
  EXPECT_NEAR(tr.com.back(), target, 1e-4);
  EXPECT_NEAR(tr.cop.back(), target, 1e-4);
  // The COM never moves the wrong way by more than a millimetre.
  EXPECT_GT(*std::min_element(tr.com.begin(), tr.com.end()), -1e-3);
}

TEST(BalanceController, ClosedLoopModelSteadyStateIsReference) {
  const BalanceController bc = make_controller();
  const ClosedLoopModel d = bc.closed_loop_model(0.005);
  // Fixed point of s = A s + B c_ref is (c_ref, c_ref, 0, 0) and the output is c_ref.
  const Vec4 s_ss = (Mat4::Identity() - d.A).inverse() * d.B * 0.1;
  EXPECT_TRUE(s_ss.isApprox(Vec4(0.1, 0.1, 0, 0), 1e-9)) << s_ss.transpose();
  EXPECT_NEAR(d.C * s_ss, 0.1, 1e-12);
  // Discretisations at different periods agree: two 5 ms steps = one 10 ms step.
  const ClosedLoopModel d2 = bc.closed_loop_model(0.010);
  EXPECT_TRUE((d.A * d.A).isApprox(d2.A, 1e-9));
  EXPECT_TRUE((d.A * d.B + d.B).isApprox(d2.B, 1e-9));
}

TEST(BalanceController, RejectsBadParameters) {
  EXPECT_THROW(BalanceController(PendulumModel{0.0, 9.81}), InputError);
  BalanceOptions o;
  o.r = 0;
  EXPECT_THROW(BalanceController(PendulumModel{0.7, 9.81}, o), InputError);
}

}  // namespace
}  // namespace rt
