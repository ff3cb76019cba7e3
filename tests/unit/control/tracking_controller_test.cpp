#include "retarget/control/tracking_controller.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

struct Fixture {
  std::unique_ptr<RobotModel> model = RobotModel::load(test::source_path("robots/humanoid25"));
  RobotData data{*model};

  // A moving state near standing, and a reference slightly away from it.
  std::pair<VecX, VecX> state(unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    VecX q = model->standing_q();
    for (int i = 7; i < model->nq(); ++i) q[i] += 0.05 * n(rng);
    VecX v(model->nv());
    for (int i = 0; i < model->nv(); ++i) v[i] = 0.3 * n(rng);
    return {q, v};
  }

  // Sole targets where the soles are at q (the feet held), and the desired COP under the COM.
  void hold_feet(TrackingReference& ref, const VecX& q) {
    update_kinematics(*model, data, q);
    for (int foot = 0; foot < 2; ++foot) {
      const Sole& s = model->soles()[static_cast<std::size_t>(foot)];
      Iso3 X = link_pose(*model, data, s.link);
      X.translation() = X * s.p_L_center;
      ref.X_W_sole[static_cast<std::size_t>(foot)] = X;
    }
    ref.desired_cop_W = com_position(*model, data).head<2>();
  }

  TrackingReference reference(const VecX& q, bool left, bool right) {
    TrackingReference ref;
    ref.q = model->standing_q();
    ref.v = VecX::Zero(model->nv());
    ref.a = VecX::Zero(model->nv());
    update_kinematics(*model, data, q);
    for (int foot = 0; foot < 2; ++foot) {
      const Sole& s = model->soles()[static_cast<std::size_t>(foot)];
      Iso3 X = link_pose(*model, data, s.link);
      X.translation() = X * s.p_L_center + Vec3(0.01, 0, 0);
      ref.X_W_sole[static_cast<std::size_t>(foot)] = X;
    }
    ref.contact = {left, right};
    ref.desired_cop_W = Vec2(0.02, 0.03);
    return ref;
  }
};

double total(const std::array<double, 8>& z) {
  double s = 0;
  for (double v : z) s += v;
  return s;
}

TEST(TrackingController, QuadraticFormMatchesTheDirectTerms) {
  Fixture fx;
  TrackingOptions with_vertical_force;
  with_vertical_force.weights.vertical_force = 1e-3;
  const TrackingController tc(*fx.model, TrackingOptions{}), tc_z(*fx.model, with_vertical_force);
  for (unsigned seed : {1u, 2u, 3u}) {
    const auto [q, v] = fx.state(seed);
    for (auto [l, r] : {std::pair{true, true}, std::pair{true, false}, std::pair{false, false}}) {
      for (const TrackingController* c : {&tc, &tc_z}) {
        TrackingReference ref = fx.reference(q, l, r);
        ref.desired_vertical_force_n = 300;
        const TrackingProblem p = c->build(fx.data, q, v, ref);
        const Eigen::Index ny = p.nu + p.nf;
        ASSERT_EQ(p.A.rows(), ny);
        std::mt19937 rng(seed);
        std::normal_distribution<double> n(0.0, 1.0);
        // Z(y) − Z(0) from the quadratic form must equal the sum of the terms evaluated directly.
        const double z0 = total(c->cost_terms(p, VecX::Zero(ny)));
        for (int trial = 0; trial < 3; ++trial) {
          VecX y(ny);
          for (Eigen::Index i = 0; i < ny; ++i) y[i] = (i < p.nu ? 20.0 : 100.0) * n(rng);
          const double quad = 0.5 * y.dot(p.A * y) + y.dot(p.b);
          const double direct = total(c->cost_terms(p, y)) - z0;
          EXPECT_NEAR(quad, direct, 1e-6 * std::max(1.0, std::abs(direct)));
        }
      }
    }
  }
}

TEST(TrackingController, SolutionIsTheMinimumAndSatisfiesTheEquationOfMotion) {
  Fixture fx;
  TrackingOptions o;
  const TrackingController tc(*fx.model, o);
  const auto [q, v] = fx.state(7);
  const TrackingProblem p = tc.build(fx.data, q, v, fx.reference(q, true, true));
  const TrackingCommand c = tc.solve(p);
  VecX y(p.nu + p.nf);
  y << c.tau_raw, c.f_contact;
  // Stationary: A y + b = 0, and every perturbation raises the directly evaluated cost.
  EXPECT_LT((p.A * y + p.b).norm(), 1e-6 * std::max(1.0, p.b.norm()));
  const double z = total(tc.cost_terms(p, y));
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    VecX d(y.size());
    for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = n(rng);
    EXPECT_GE(total(tc.cost_terms(p, y + 1e-3 * d)), z - 1e-9);
  }
  // Eq. (6): M q̈ + c = S τ + J_fᵀ f with the q̈ the controller reports.
  VecX rhs = p.J_contact.transpose() * c.f_contact;
  rhs.tail(p.nu) += c.tau_raw;
  EXPECT_LT((p.M * c.qdd + p.bias - rhs).norm(), 1e-8 * std::max(1.0, rhs.norm()));
}

// The contact-limit rows of one foot are the contact wrench cone of its (shrunk) sole rectangle:
// every wrench made of forces inside the friction pyramid at its four corners satisfies them,
// and a yaw moment about a single loaded corner (which no contact can hold) violates them.
TEST(TrackingController, ContactLimitsAreTheWrenchConeOfTheSoleCorners) {
  Fixture fx;
  TrackingOptions o;
  const TrackingController tc(*fx.model, o);
  const auto [q, v] = fx.state(5);
  const TrackingProblem p = tc.build(fx.data, q, v, fx.reference(q, true, false));
  ASSERT_EQ(p.contact_feet.size(), 1u);
  const Sole& sole = fx.model->soles()[static_cast<std::size_t>(p.contact_feet[0])];
  const double X = 0.5 * o.contact.cop_margin * sole.size_m.x(), Y = 0.5 * o.contact.cop_margin * sole.size_m.y();
  const double mu = o.contact.friction_margin * fx.model->config().simulation.friction / std::sqrt(2.0);
  const Mat3& R = p.R_contact_W[0];
  const auto wrench_W = [&](const Vec3& f_S, const Vec3& n_S) {
    VecX w(6);
    w << R * f_S, R * n_S;
    return w;
  };
  const auto margin = [&](const VecX& w) { return (p.C_contact * w - p.d_contact).minCoeff(); };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::array<Vec2, 4> corners = {Vec2(X, Y), Vec2(-X, Y), Vec2(-X, -Y), Vec2(X, -Y)};
  for (int trial = 0; trial < 2000; ++trial) {
    Vec3 f_S = Vec3::Zero(), n_S = Vec3::Zero();
    for (const Vec2& c : corners) {
      const double fz = trial % 4 == 0 && u(rng) < 0.5 ? 0.0 : 100 * u(rng);
      // Pyramid edges half of the time (where the bounds are tight), inside otherwise.
      const double sx = trial % 2 ? (u(rng) < 0.5 ? -1.0 : 1.0) : 2 * u(rng) - 1;
      const double sy = trial % 2 ? (u(rng) < 0.5 ? -1.0 : 1.0) : 2 * u(rng) - 1;
      const Vec3 f(sx * mu * fz, sy * mu * fz, fz);
      f_S += f;
      n_S += Vec3(c.x(), c.y(), 0).cross(f);
    }
    EXPECT_GE(margin(wrench_W(f_S, n_S)), -1e-9 * std::max(1.0, f_S.z())) << "trial " << trial;
  }
  const double fz = 300;
  // COP at the centre: a yaw moment of μ' min(X, Y) f_z / 2 is held; at a corner none is.
  EXPECT_GE(margin(wrench_W(Vec3(0, 0, fz), Vec3(0, 0, 0.5 * mu * std::min(X, Y) * fz))), 0.0);
  EXPECT_LT(margin(wrench_W(Vec3(0, 0, fz), Vec3(Y * fz, -X * fz, 0.5 * mu * std::min(X, Y) * fz))), 0.0);
}

TEST(TrackingController, StandingNeedsSupportForcesEqualToWeight) {
  Fixture fx;
  const TrackingController tc(*fx.model, TrackingOptions{});
  const VecX q = fx.model->standing_q();
  const VecX v = VecX::Zero(fx.model->nv());
  TrackingReference ref = fx.reference(q, true, true);
  fx.hold_feet(ref, q);
  const TrackingCommand c = tc.compute(fx.data, q, v, ref);
  const double weight = fx.model->total_mass_kg() * 9.81;
  const double fz = c.f_contact[2] + c.f_contact[8];
  EXPECT_NEAR(fz, weight, 0.05 * weight);
  EXPECT_EQ(c.saturated_joints, 0);
}

// The walking controller's force ramp: a cap on one foot's normal force moves the load to the other
// foot (the QP row f_z <= f_max), and without a cap the solution is the uncapped one.
TEST(TrackingController, NormalForceCapMovesTheLoadToTheOtherFoot) {
  Fixture fx;
  const TrackingController tc(*fx.model, TrackingOptions{});
  const VecX q = fx.model->standing_q();
  const VecX v = VecX::Zero(fx.model->nv());
  TrackingReference ref = fx.reference(q, true, true);
  fx.hold_feet(ref, q);
  const TrackingCommand free = tc.compute(fx.data, q, v, ref);
  const double weight = fx.model->total_mass_kg() * 9.81;
  ASSERT_GT(free.f_contact[8], 0.3 * weight);  // the right foot carries a good part without a cap
  ref.max_normal_force_n = {std::numeric_limits<double>::infinity(), 0.1 * weight};
  const TrackingCommand capped = tc.compute(fx.data, q, v, ref);
  EXPECT_LE(capped.f_contact[8], 0.1 * weight + 1e-6);
  EXPECT_NEAR(capped.f_contact[2] + capped.f_contact[8], weight, 0.05 * weight);
  EXPECT_FALSE(capped.closed_form_feasible);
}

// Effort limits inside the optimisation: when the closed form asks a joint for more than its
// limit, the torque-limited problem over (τ, f) respects every limit, costs no more than clipping
// that demand would, and keeps the equation of motion; the demand is still reported as saturation.
TEST(TrackingController, TorqueLimitsAreConstraintsNotClipping) {
  Fixture fx;
  const VecX q = fx.model->standing_q();
  const VecX v = VecX::Zero(fx.model->nv());
  TrackingReference ref = fx.reference(q, true, true);
  fx.hold_feet(ref, q);
  // A violent acceleration asked of every joint: far beyond what the effort limits allow.
  ref.a.tail(fx.model->nu()).setConstant(400.0);
  TrackingOptions clip_only;
  clip_only.torque_limits = false;
  const TrackingController clipping(*fx.model, clip_only);
  const TrackingController limited(*fx.model, TrackingOptions{});
  const TrackingProblem p = limited.build(fx.data, q, v, ref);
  const TrackingCommand a = clipping.solve(p), b = limited.solve(p);
  ASSERT_GT(a.saturated_joints, 0);
  EXPECT_FALSE(a.torque_limited);
  ASSERT_TRUE(b.torque_limited);
  EXPECT_EQ(b.saturated_joints, a.saturated_joints);  // judged on the same unconstrained demand
  const VecX& limit = fx.model->effort_limits();
  for (int i = 0; i < p.nu; ++i) {
    if (limit[i] > 0) {
      EXPECT_LE(std::abs(b.tau[i]), limit[i] * (1 + 1e-9) + 1e-9) << "joint " << i;
    }
  }
  auto y_of = [&](const TrackingCommand& c) {
    VecX y(p.nu + p.nf);
    y << c.tau, c.f_contact;
    return y;
  };
  // Clipping is one feasible point of the torque-limited problem; its optimum is no worse.
  EXPECT_LT(total(limited.cost_terms(p, y_of(b))), total(limited.cost_terms(p, y_of(a))));
  VecX rhs = p.J_contact.transpose() * b.f_contact;
  rhs.tail(p.nu) += b.tau;
  EXPECT_LT((p.M * b.qdd + p.bias - rhs).norm(), 1e-8 * std::max(1.0, rhs.norm()));
  // Nothing saturated: identical to the closed form.
  ref.a.setZero();
  const TrackingProblem calm = limited.build(fx.data, q, v, ref);
  const TrackingCommand c = limited.solve(calm), d = clipping.solve(calm);
  EXPECT_FALSE(c.torque_limited);
  EXPECT_LT((c.tau - d.tau).norm(), 1e-12);
}

}  // namespace
}  // namespace rt
