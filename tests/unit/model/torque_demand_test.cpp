// The torque demand of the joints above the feet: which joints it judges, its static value against
// MuJoCo's bias forces, and how it grows with the motion's speed.
#include "retarget/model/torque_demand.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>

#include "model_cache.hpp"
#include "support/test_paths.hpp"
#include "retarget/model/kinematics.hpp"

namespace rt {
namespace {

const RobotModel& humanoid25() { return test::cached_robot(test::source_path("robots/humanoid25")); }

// T frames at `fps` of the standing pose with every joint not carrying a foot swinging by `amp` of
// its range about the middle at `omega` [rad/s].
MatX swinging_arms(const RobotModel& model, int T, double fps, double amp, double omega) {
  const std::vector<bool> foot = joints_carrying_a_foot(model);
  MatX q(model.nq(), T);
  for (int f = 0; f < T; ++f) {
    VecX x = model.standing_q();
    for (int i = 0; i < model.nu(); ++i) {
      if (foot[static_cast<std::size_t>(i)]) continue;
      const double lo = model.q_lower()[i], hi = model.q_upper()[i];
      x[7 + i] = 0.5 * (lo + hi) + amp * 0.5 * (hi - lo) * std::sin(omega * f / fps + i);
    }
    q.col(f) = x;
  }
  return q;
}

TEST(TorqueDemand, JudgesExactlyTheJointsThatMoveNoSole) {
  const RobotModel& model = humanoid25();
  RobotData data(model);
  const std::vector<bool> foot = joints_carrying_a_foot(model);
  int carrying = 0;
  for (int i = 0; i < model.nu(); ++i) {
    // Independently: does turning this joint alone move or turn a sole link?
    VecX q = model.standing_q();
    update_kinematics(model, data, q);
    std::array<Iso3, 2> before;
    for (int s = 0; s < 2; ++s) before[static_cast<std::size_t>(s)] = link_pose(model, data, model.soles()[static_cast<std::size_t>(s)].link);
    q[7 + i] += 0.1;
    update_kinematics(model, data, q);
    bool moved = false;
    for (int s = 0; s < 2; ++s)
      moved = moved || !link_pose(model, data, model.soles()[static_cast<std::size_t>(s)].link).isApprox(before[static_cast<std::size_t>(s)], 1e-9);
    EXPECT_EQ(foot[static_cast<std::size_t>(i)], moved) << model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(i)])].name;
    carrying += moved;
  }
  EXPECT_EQ(carrying, 12);  // two six-joint legs
}

TEST(TorqueDemand, StandingStillAsksTheGravityTorques) {
  const RobotModel& model = humanoid25();
  RobotData data(model);
  const MatX q = swinging_arms(model, 5, 30, 0.3, 0.0);  // omega 0: a still pose with the arms out
  const TorqueDemand d = torque_demand(model, data, q, 30);
  EXPECT_EQ(d.frames, 3);
  // The gravity torques of that pose from MuJoCo's bias forces (zero velocity).
  mjData* md = data.mj();
  for (int k = 0; k < model.nq(); ++k) md->qpos[k] = q(k, 2);
  for (int k = 0; k < model.nv(); ++k) md->qvel[k] = 0;
  mj_forward(model.mj(), md);
  double expected = 0;
  for (int i = 0; i < model.nu(); ++i)
    if (d.judged[static_cast<std::size_t>(i)]) expected = std::max(expected, std::abs(md->qfrc_bias[6 + i]) / model.effort_limits()[i]);
  EXPECT_GT(expected, 0.0);
  EXPECT_NEAR(d.max_ratio, expected, 1e-6 * expected);
}

TEST(TorqueDemand, GrowsWithTheSpeedOfTheMotion) {
  const RobotModel& model = humanoid25();
  RobotData data(model);
  const TorqueDemand slow = torque_demand(model, data, swinging_arms(model, 60, 30, 0.3, 1.0), 30);
  const TorqueDemand fast = torque_demand(model, data, swinging_arms(model, 60, 30, 0.3, 12.0), 30);
  EXPECT_EQ(slow.frames_over, 0);
  EXPECT_GT(fast.max_ratio, 3 * slow.max_ratio);
  EXPECT_GT(fast.frames_over, 0);
  ASSERT_GE(fast.max_joint, 0);
  EXPECT_FALSE(joints_carrying_a_foot(model)[static_cast<std::size_t>(fast.max_joint)]);
  EXPECT_NEAR(fast.max_ratio, fast.joint_max_ratio[static_cast<std::size_t>(fast.max_joint)], 1e-12);
}

}  // namespace
}  // namespace rt
