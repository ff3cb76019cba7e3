// The violation monitor's slip measure: a loaded stance foot that spins on the spot (its centre
// still) slides at its toe and heel, and is reported; a foot that stands still is not.

#include "retarget/sim/violation_monitor.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// Observes 0.1 s of a standing humanoid25 whose left foot (the only one in the reference's stance,
// loaded) turns about the vertical through its sole centre at `yaw_rate` [rad/s].
std::vector<Violation> spin_left_foot(double yaw_rate) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  RobotData data(*model);
  const VecX q = model->standing_q();
  update_kinematics(*model, data, q);
  // Root angular velocity about z, and the root linear velocity that keeps the left sole centre still.
  VecX v = VecX::Zero(model->nv());
  v[5] = yaw_rate;
  const Sole& sole = model->soles()[0];
  const MatX J = link_jacobian(*model, data, sole.link, sole.p_L_center);
  v.head<3>() = -(J.topRows<3>() * v);
  EXPECT_LT((J.topRows<2>() * v).norm(), 1e-9);  // the centre does not move
  update_dynamics(*model, data, q, v);

  DynamicsCheckOptions options;
  ViolationMonitor monitor(*model, options);
  ContactState contacts;
  contacts.feet[0].normal_force_n = contacts.normal_force_n = model->total_mass_kg() * 9.81;
  contacts.feet[0].cop_W = contacts.cop_W = (link_pose(*model, data, sole.link) * sole.p_L_center).head<2>();
  FootStates feet;
  feet.loaded = {true, false};
  feet.on_floor = {true, false};
  ControlOutput out;
  out.reference.q = q;
  out.reference.v = VecX::Zero(model->nv());
  out.reference.contact = {true, false};
  out.tracking.q = q;
  out.tracking.contact = {true, false};
  out.tracking.X_W_sole[0] = link_pose(*model, data, sole.link);
  out.command.tau = out.command.tau_raw = VecX::Zero(model->nu());
  out.command.f_contact = VecX::Zero(6);
  out.command.f_contact[2] = contacts.normal_force_n;
  for (int k = 0; k <= 50; ++k) {
    ControlInput in;
    in.t_clip_s = in.t_sim_s = in.t_signal_s = in.t_ref_s = 0.002 * k;
    in.q = &q;
    in.v = &v;
    in.contacts = &contacts;
    in.feet = &feet;
    in.data = &data;
    in.com_W = com_position(*model, data);
    monitor.observe(in, out);
  }
  DynamicsCheckResult result;
  monitor.finish(0.1, result);
  std::vector<Violation> slips;
  for (const Violation& x : result.violations)
    if (x.kind == ViolationKind::FootSlip) slips.push_back(x);
  return slips;
}

TEST(ViolationMonitor, AFootSpinningOnTheSpotSlides) {
  const std::vector<Violation> slips = spin_left_foot(3.0);
  ASSERT_EQ(slips.size(), 1u);
  // Its corners move at about 3 rad/s times half the sole's diagonal.
  EXPECT_GT(slips[0].magnitude, 0.2);
  EXPECT_NE(slips[0].detail.find("left foot"), std::string::npos) << slips[0].detail;
  EXPECT_NE(slips[0].detail.find("centre 0.000 m/s, turning 3.00 rad/s"), std::string::npos) << slips[0].detail;
}

TEST(ViolationMonitor, AFootStandingStillDoesNotSlide) { EXPECT_TRUE(spin_left_foot(0.0).empty()); }

}  // namespace
}  // namespace rt
