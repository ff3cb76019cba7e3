// The violation monitor's slip measure: a loaded stance foot that spins on the spot (its centre
// still) slides at its toe and heel, and is reported; a foot that stands still is not. Its
// contact timing: a foot that does not lift during a swing shorter than the contact tolerance is
// still reported, since the tolerance is bounded by a fraction of the phase. A stance foot that
// slides away from its footstep fails the check, and so does a reference that moves a joint faster
// than its velocity limit.

#include "retarget/sim/violation_monitor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/model/torque_demand.hpp"
#include "retarget/sim/reference_consistency.hpp"
#include "retarget/sim/reference_signal.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// One control cycle at clip time `t_s` of the robot in state (q, v); `data` current for it.
void observe_at(ViolationMonitor& monitor, double t_s, const RobotModel& model, RobotData& data, const VecX& q, const VecX& v,
                const ContactState& contacts, const FootStates& feet, const ControlOutput& out) {
  ControlInput in;
  in.t_clip_s = in.t_sim_s = in.t_signal_s = in.t_ref_s = t_s;
  in.q = &q;
  in.v = &v;
  in.contacts = &contacts;
  in.feet = &feet;
  in.data = &data;
  in.com_W = com_position(model, data);
  monitor.observe(in, out);
}

// The violations of `kind` once the monitor is finished at `t_end_s`.
std::vector<Violation> violations_of(ViolationMonitor& monitor, double t_end_s, ViolationKind kind) {
  DynamicsCheckResult result;
  monitor.finish(t_end_s, result);
  std::vector<Violation> found;
  for (const Violation& x : result.violations)
    if (x.kind == kind) found.push_back(x);
  return found;
}

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
  const std::array<std::vector<std::uint8_t>, 2> schedule{{std::vector<std::uint8_t>(11, 1), std::vector<std::uint8_t>(11, 0)}};
  ViolationMonitor monitor(*model, options, schedule, 100.0);
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
  for (int k = 0; k <= 50; ++k) observe_at(monitor, 0.002 * k, *model, data, q, v, contacts, feet, out);
  return violations_of(monitor, 0.1, ViolationKind::FootSlip);
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


// A standing humanoid25 observed for 1 s while the reference (100 fps) lifts the right foot from
// 0.5 s for `swing_s`; the robot's right foot stays loaded on the floor for `late_s` of that swing
// and then lifts: the lift-off violations reported.
std::vector<Violation> right_foot_lifts_late(double swing_s, double late_s, const DynamicsCheckOptions& options) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  RobotData data(*model);
  const VecX q = model->standing_q();
  const VecX v = VecX::Zero(model->nv());
  update_dynamics(*model, data, q, v);
  constexpr double kFps = 100;
  std::array<std::vector<std::uint8_t>, 2> schedule{{std::vector<std::uint8_t>(101, 1), std::vector<std::uint8_t>(101, 1)}};
  const auto lift = static_cast<std::size_t>(0.5 * kFps), land = static_cast<std::size_t>(std::lround((0.5 + swing_s) * kFps));
  std::fill(schedule[1].begin() + static_cast<std::ptrdiff_t>(lift), schedule[1].begin() + static_cast<std::ptrdiff_t>(land), 0);
  ViolationMonitor monitor(*model, options, schedule, kFps);
  ContactState contacts;
  contacts.normal_force_n = model->total_mass_kg() * 9.81;
  for (int f = 0; f < 2; ++f) {
    const Sole& sole = model->soles()[static_cast<std::size_t>(f)];
    contacts.feet[static_cast<std::size_t>(f)].normal_force_n = 0.5 * contacts.normal_force_n;
    contacts.feet[static_cast<std::size_t>(f)].cop_W = (link_pose(*model, data, sole.link) * sole.p_L_center).head<2>();
  }
  contacts.cop_W = 0.5 * (contacts.feet[0].cop_W + contacts.feet[1].cop_W);
  FootStates feet;
  feet.loaded = {true, true};
  feet.on_floor = {true, true};
  ControlOutput out;
  out.reference.q = out.tracking.q = q;
  out.reference.v = v;
  out.command.tau = out.command.tau_raw = VecX::Zero(model->nu());
  out.tracking.contact = {false, false};  // no commanded wrenches to judge
  out.command.f_contact = VecX::Zero(0);
  for (int k = 0; k <= 500; ++k) {
    const double t = 0.002 * k;
    out.reference.contact = {true, schedule[1][static_cast<std::size_t>(std::lround(t * kFps))] != 0};
    const bool right_down = out.reference.contact[1] || t < 0.5 + late_s;
    feet.loaded[1] = feet.on_floor[1] = right_down;
    contacts.feet[1].normal_force_n = right_down ? contacts.feet[0].normal_force_n : 0.0;
    observe_at(monitor, t, *model, data, q, v, contacts, feet, out);
  }
  return violations_of(monitor, 1.0, ViolationKind::LiftOffNotAchieved);
}

TEST(ViolationMonitor, AFootThatDoesNotLiftInAShortSwingIsReported) {
  // A 0.12 s swing: shorter than the 0.15 s tolerance, so only its bound by half the phase (0.06 s)
  // can tell that the foot never left the floor.
  const DynamicsCheckOptions options;
  ASSERT_GT(options.contact_tolerance_s, 0.12);
  const std::vector<Violation> stuck = right_foot_lifts_late(0.12, 0.12, options);
  ASSERT_EQ(stuck.size(), 1u);
  EXPECT_NEAR(stuck[0].start_s, 0.5, 0.006);
  EXPECT_NE(stuck[0].detail.find("right foot"), std::string::npos) << stuck[0].detail;
  // Without the bound the same miss goes unreported.
  DynamicsCheckOptions unbounded;
  unbounded.contact_tolerance_fraction = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(right_foot_lifts_late(0.12, 0.12, unbounded).empty());
  // A lift 0.04 s late in that swing is within the bound; a long swing keeps the full tolerance:
  // 0.12 s late in a 0.4 s swing is within it, the whole swing is not.
  EXPECT_TRUE(right_foot_lifts_late(0.12, 0.04, options).empty());
  EXPECT_TRUE(right_foot_lifts_late(0.4, 0.12, options).empty());
  EXPECT_EQ(right_foot_lifts_late(0.4, 0.4, options).size(), 1u);
}


// A humanoid25 in its standing pose, both feet loaded and in the reference's stance, observed for
// 0.5 s while `motion(t, q, v)` sets its state: the violations reported of `kind`.
std::vector<Violation> observe_standing(const std::function<void(double, VecX&, VecX&)>& motion, ViolationKind kind) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  RobotData data(*model);
  const std::array<std::vector<std::uint8_t>, 2> schedule{{std::vector<std::uint8_t>(51, 1), std::vector<std::uint8_t>(51, 1)}};
  const DynamicsCheckOptions options;
  ViolationMonitor monitor(*model, options, schedule, 100.0);
  ContactState contacts;
  contacts.normal_force_n = model->total_mass_kg() * 9.81;
  for (auto& foot : contacts.feet) foot.normal_force_n = 0.5 * contacts.normal_force_n;
  FootStates feet;
  feet.loaded = feet.on_floor = {true, true};
  ControlOutput out;
  out.reference.q = out.tracking.q = model->standing_q();
  out.reference.v = VecX::Zero(model->nv());
  out.reference.contact = {true, true};
  out.tracking.contact = {false, false};  // no commanded wrenches to judge
  out.command.tau = out.command.tau_raw = VecX::Zero(model->nu());
  for (int k = 0; k <= 250; ++k) {
    VecX q = model->standing_q(), v = VecX::Zero(model->nv());
    motion(0.002 * k, q, v);
    update_dynamics(*model, data, q, v);
    observe_at(monitor, 0.002 * k, *model, data, q, v, contacts, feet, out);
  }
  return violations_of(monitor, 0.5, kind);
}

// The whole robot, both loaded feet with it, slides forward by `distance_m` over 0.5 s.
std::vector<Violation> slide_forward(double distance_m) {
  return observe_standing(
      [distance_m](double t, VecX& q, VecX& v) {
        q[0] += distance_m * t / 0.5;
        v[0] = distance_m / 0.5;
      },
      ViolationKind::StanceFootMoved);
}

TEST(ViolationMonitor, AStanceFootThatSlidesOffItsFootstepFailsTheCheck) {
  const std::vector<Violation> moved = slide_forward(0.08);
  ASSERT_EQ(moved.size(), 2u);  // both feet
  EXPECT_TRUE(violation_fails_check(ViolationKind::StanceFootMoved));
  for (const Violation& x : moved) {
    EXPECT_NEAR(x.start_s, 0.05 / 0.08 * 0.5, 0.01);  // when it is 5 cm off
    EXPECT_NEAR(x.magnitude, 0.08, 1e-3);
  }
  EXPECT_NE(moved[0].detail.find("turned 0 deg"), std::string::npos) << moved[0].detail;
  // Within the bound: kept its footstep (the slip itself is a foot-slip warning).
  EXPECT_TRUE(slide_forward(0.04).empty());
}

// A standing humanoid25 reference (100 fps) whose first leg joint moves at `ratio` times its URDF
// velocity limit from 0.2 s to 0.25 s: the reference's own joint-velocity violations.
std::vector<Violation> reference_moving_joint_at(double ratio, std::string* name = nullptr) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  const double vmax = model->velocity_limits()[0];
  EXPECT_GT(vmax, 0);
  const std::string joint = model->joints()[static_cast<std::size_t>(model->movable_joints()[0])].name;
  if (name) *name = joint;
  Reference ref = constant_reference(*model, model->standing_q(), 0.5, 100.0);
  const auto row = std::find(ref.joint_names.begin(), ref.joint_names.end(), joint) - ref.joint_names.begin();
  for (int k = 0; k < ref.num_frames(); ++k)
    ref.joint_pos(row, k) += ratio * vmax * std::clamp(k / 100.0 - 0.2, 0.0, 0.05);
  RobotData data(*model);
  return reference_joint_speed(*model, ReferenceSignal(*model, data, ref), 0.0);
}

TEST(ReferenceJointSpeed, AReferenceFasterThanAJointsVelocityLimitFailsTheCheck) {
  std::string joint;
  const std::vector<Violation> fast = reference_moving_joint_at(1.5, &joint);
  ASSERT_EQ(fast.size(), 1u);
  EXPECT_EQ(fast[0].kind, ViolationKind::JointVelocity);
  EXPECT_TRUE(violation_fails_check(ViolationKind::JointVelocity));
  EXPECT_NEAR(fast[0].start_s, 0.2, 0.011);
  EXPECT_NEAR(fast[0].end_s, 0.25, 0.011);
  EXPECT_NEAR(fast[0].magnitude, 1.5, 1e-6);
  EXPECT_NE(fast[0].detail.find(joint), std::string::npos) << fast[0].detail;
  EXPECT_TRUE(reference_moving_joint_at(0.9).empty());
}

// A standing humanoid25 reference (100 fps) that swings one arm joint (the first joint with no foot
// below it) by `amplitude` rad at `omega` rad/s from 0.2 s to 0.4 s: the reference's own torque
// demand of that joint.
std::vector<Violation> reference_swinging_arm(double amplitude, double omega, std::string* name = nullptr) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  const std::vector<bool> foot = joints_carrying_a_foot(*model);
  int arm = -1;
  for (int i = 0; i < model->nu() && arm < 0; ++i)
    if (!foot[static_cast<std::size_t>(i)] && model->effort_limits()[i] > 0) arm = i;
  EXPECT_GE(arm, 0);
  const std::string joint = model->joints()[static_cast<std::size_t>(model->movable_joints()[static_cast<std::size_t>(arm)])].name;
  if (name) *name = joint;
  Reference ref = constant_reference(*model, model->standing_q(), 0.6, 100.0);
  const auto row = std::find(ref.joint_names.begin(), ref.joint_names.end(), joint) - ref.joint_names.begin();
  for (int k = 0; k < ref.num_frames(); ++k) {
    const double t = k / 100.0;
    if (t > 0.2 && t < 0.4) ref.joint_pos(row, k) += amplitude * std::pow(std::sin(M_PI * (t - 0.2) / 0.2), 2) * std::sin(omega * (t - 0.2));
  }
  RobotData data(*model);
  return reference_torque_demand(*model, data, ReferenceSignal(*model, data, ref), 0.0);
}

TEST(ReferenceTorqueDemand, AnArmSwungFasterThanItsMotorCanIsReportedNotFailed) {
  std::string joint;
  const std::vector<Violation> fast = reference_swinging_arm(0.3, 60.0, &joint);
  ASSERT_FALSE(fast.empty());
  for (const Violation& v : fast) {
    EXPECT_EQ(v.kind, ViolationKind::ReferenceTorque);
    EXPECT_GT(v.start_s, 0.19);
    EXPECT_LT(v.end_s, 0.41);
    EXPECT_GT(v.magnitude, 1.0);
    EXPECT_NE(v.detail.find(joint), std::string::npos) << v.detail;
  }
  EXPECT_FALSE(violation_fails_check(ViolationKind::ReferenceTorque));
  // The same swing, slow: within the motor's torque.
  EXPECT_TRUE(reference_swinging_arm(0.3, 3.0).empty());
}

}  // namespace
}  // namespace rt
