// single_support_reach (ik/single_support_reach.hpp): whether the COM can be brought over one sole
// with the other foot lifted. humanoid25 can (and the check passes its foot lift); the same robot
// with its sideways joints locked cannot (a negative control that needs no shared data); the
// shared Unitree H1 (wide hips, no ankle roll, 3 cm soles) cannot either.

#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
#include <string>

#include "retarget/core/file_io.hpp"
#include "retarget/ik/single_support_reach.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

TEST(SingleSupportReach, Humanoid25StandsOnEitherFoot) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  const auto reach = single_support_reach(*model);
  for (const SingleSupportReach& r : reach) {
    EXPECT_LT(r.com_to_centre_m, 0.005);
    EXPECT_EQ(r.com_outside_sole_m, 0.0);
    EXPECT_GT(r.standing_com_to_centre_m, 0.05);  // it had to move: the feet are apart
    // The reached pose keeps the joint limits and the held sole where it stood.
    for (int i = 0; i < model->nu(); ++i) {
      EXPECT_GE(r.q[7 + i], model->q_lower()[i] - 1e-9);
      EXPECT_LE(r.q[7 + i], model->q_upper()[i] + 1e-9);
    }
  }
  RobotData stand(*model), reached(*model);
  update_kinematics(*model, stand, model->standing_q());
  update_kinematics(*model, reached, reach[0].q);
  const Sole& left = model->soles()[0];
  EXPECT_LT((link_point(*model, reached, left.link, left.p_L_center) - link_point(*model, stand, left.link, left.p_L_center))
                .norm(),
            1e-3);
  EXPECT_TRUE(check_single_support(*model, reach).empty());
}

TEST(SingleSupportReach, LockedSidewaysJointsAndNarrowSolesCannotStandOnOneFoot) {
  // humanoid25 with its hip and ankle rolls, hip yaws and waist yaw limited to +-0.02 rad: the
  // stance leg cannot lean sideways nor the pelvis roll, and the trunk cannot turn its pitch into a
  // sideways lean; arms, trunk pitch and knees still move the COM some 5 cm sideways, so the soles
  // are narrowed to 3 cm (as H1's) for the COM to stay outside them.
  std::string urdf = read_file(test::source_path("robots/humanoid25/humanoid25.urdf"));
  for (const char* name : {"l_hip_roll", "r_hip_roll", "l_ankle_roll", "r_ankle_roll", "l_hip_yaw", "r_hip_yaw", "waist_yaw"}) {
    const std::regex joint(std::string("(<joint name=\"") + name + "\"[\\s\\S]*?<limit )lower=\"[^\"]*\" upper=\"[^\"]*\"");
    urdf = std::regex_replace(urdf, joint, "$1lower=\"-0.02\" upper=\"0.02\"", std::regex_constants::format_first_only);
  }
  const std::string dir = test::scratch_dir();
  write_file_atomic(dir + "/humanoid25.urdf", urdf);
  std::string yaml = read_file(test::source_path("robots/humanoid25/robot.yaml"));
  yaml = std::regex_replace(yaml, std::regex("size: \\[0\\.22, 0\\.10\\]"), "size: [0.22, 0.03]");
  write_file_atomic(dir + "/robot.yaml", yaml);
  const auto model = RobotModel::load(dir + "/robot.yaml");
  ASSERT_NEAR(model->soles()[0].size_m.y(), 0.03, 1e-12);
  ASSERT_LE(model->q_upper()[model->joints()[static_cast<std::size_t>(model->find_joint("l_hip_roll"))].qpos_index - 7], 0.021);
  const auto reach = single_support_reach(*model);
  for (const SingleSupportReach& r : reach) EXPECT_GT(r.com_outside_sole_m, 0.02);
  const Diagnostics d = check_single_support(*model, reach);
  ASSERT_EQ(d.warning_count(), 2u);
  EXPECT_NE(d.items()[0].to_string().find("cannot stand on its left foot"), std::string::npos) << d.items()[0].to_string();
}

TEST(SingleSupportReach, UnitreeH1CannotStandOnOneFoot) {
  RT_REQUIRE_SHARED(urdf, "robots/unitree_h1/h1_description/urdf/h1.urdf");
  const auto model = RobotModel::load(test::source_path("robots/h1"));
  const auto reach = single_support_reach(*model);
  // Its feet stand 0.2 m either side of the COM; hip roll (+-0.43 rad) and arms bring it about
  // 13 cm over, a sole 3 cm wide needs 20 cm.
  for (const SingleSupportReach& r : reach) {
    EXPECT_GT(r.standing_com_to_centre_m, 0.18);
    EXPECT_GT(r.com_outside_sole_m, 0.03);
  }
  EXPECT_EQ(check_single_support(*model, reach).warning_count(), 2u);
}

}  // namespace
}  // namespace rt
