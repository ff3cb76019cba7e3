// Joint groups from the kinematic tree (robot.yaml controller.group_gains): G1 has 6 leg joints per
// leg, 7 per arm and 3 waist joints; group gains reach the check's tracking gains, and a joint's own
// gains override its group's.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "retarget/model/joint_groups.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/sim/dynamics_check.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

TEST(JointGroups, G1LegsArmsTorso) {
  if (test::shared_data("robots").empty()) GTEST_SKIP() << "shared robot data absent";
  const auto model = RobotModel::load(test::source_path("robots/g1"));
  const std::vector<JointGroup> g = joint_groups(*model);
  ASSERT_EQ(static_cast<int>(g.size()), model->nu());
  EXPECT_EQ(std::count(g.begin(), g.end(), JointGroup::Legs), 12);
  EXPECT_EQ(std::count(g.begin(), g.end(), JointGroup::Arms), 14);
  EXPECT_EQ(std::count(g.begin(), g.end(), JointGroup::Torso), 3);
  const int waist = model->joint_index("waist_yaw_joint");
  const int i = model->joints()[static_cast<std::size_t>(waist)].qpos_index - 7;
  EXPECT_EQ(g[static_cast<std::size_t>(i)], JointGroup::Torso);
}

TEST(JointGroups, GroupGainsReachTheCheckAndJointGainsOverrideThem) {
  const std::string dir = test::scratch_dir();
  const std::string robot = test::source_path("robots/humanoid25/robot.yaml");
  std::ifstream in(robot);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find("controller:");
  ASSERT_NE(at, std::string::npos);
  const auto end = text.find("\n\n", at);
  text.replace(at, end - at,
               "controller:\n  kp: 36\n  kd: 12\n  group_gains:\n    legs: {kp: 100, kd: 20}\n    arms: {kp: 16}\n"
               "  joint_gains:\n    l_knee: {kp: 200, kd: 30}\n  foot_gains: {kp: 900}");
  // The copy refers to the URDF beside the original.
  const auto urdf = text.find("urdf:");
  ASSERT_NE(urdf, std::string::npos);
  const auto eol = text.find('\n', urdf);
  text.replace(urdf, eol - urdf, "urdf: " + test::source_path("robots/humanoid25/humanoid25.urdf"));
  std::ofstream(dir + "/robot.yaml") << text;
  const auto model = RobotModel::load(dir + "/robot.yaml");
  const DynamicsCheckOptions o = default_check_options(*model);
  const std::vector<JointGroup> g = joint_groups(*model);
  ASSERT_EQ(o.tracking.kp_joint.size(), model->nu());
  const int knee = model->joints()[static_cast<std::size_t>(model->joint_index("l_knee"))].qpos_index - 7;
  for (int i = 0; i < model->nu(); ++i) {
    if (i == knee) {
      EXPECT_EQ(o.tracking.kp_joint[i], 200);
      EXPECT_EQ(o.tracking.kd_joint[i], 30);
    } else if (g[static_cast<std::size_t>(i)] == JointGroup::Legs) {
      EXPECT_EQ(o.tracking.kp_joint[i], 100);
      EXPECT_EQ(o.tracking.kd_joint[i], 20);
    } else if (g[static_cast<std::size_t>(i)] == JointGroup::Arms) {
      EXPECT_EQ(o.tracking.kp_joint[i], 16);
      EXPECT_EQ(o.tracking.kd_joint[i], 12);  // the default kd: arms set only kp
    } else {
      EXPECT_EQ(o.tracking.kp_joint[i], 36);
    }
  }
  EXPECT_GT(std::count(g.begin(), g.end(), JointGroup::Arms), 0);
  // The feet's task-space gains (walking controller): kd defaults to critical damping.
  EXPECT_EQ(o.walking.foot_kp, 900);
  EXPECT_EQ(o.walking.foot_kd, 60);
  const DynamicsCheckOptions d = default_check_options(*RobotModel::load(robot));
  EXPECT_EQ(d.walking.foot_kp, WalkingControllerOptions{}.foot_kp);
}

}  // namespace
}  // namespace rt
