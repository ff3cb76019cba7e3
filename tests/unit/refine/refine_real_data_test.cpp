// Walking clips from the shared data (skipped when absent) on humanoid25 and G1: the acceptance
// metrics of issue 4 after refine + ground (design.md §6 definitions, quality.hpp).

#include <gtest/gtest.h>

#include "refine_test_util.hpp"

namespace rt {
namespace {

void expect_acceptance(const std::string& robot, const std::string& relative, int frames = 0) {
  RT_REQUIRE_SHARED(path, relative);
  const RobotModel& model = test::robot(robot);
  const test::Converted c = test::convert(model, path, frames);
  ASSERT_NE(c.refine, nullptr);
  SCOPED_TRACE(robot + " " + relative);
  EXPECT_EQ(c.refine->get("failed-windows", -1), 0);
  EXPECT_EQ(c.quality.position_limit_violations, 0);
  EXPECT_EQ(c.quality.velocity_limit_violations, 0);
  EXPECT_LE(c.quality.foot_skating_p95_m, 0.01);
  EXPECT_LE(c.quality.penetration_max_m, 0.002);
  EXPECT_LT(c.quality.jitter_rad_s3, c.quality.jitter_per_frame_ik_rad_s3);
  EXPECT_LT(c.quality.frame0_sole_tilt_deg, 0.5);
  EXPECT_LT(std::abs(c.quality.frame0_sole_height_m), 0.001);
  ::testing::Test::RecordProperty("landmark_error_median_m", std::to_string(c.quality.landmark_error_median_m));
}

TEST(RefineRealData, CmuWalkG1) { expect_acceptance("g1", "bvh/cmu_max_131_01_start_walk_stop.bvh"); }
TEST(RefineRealData, CmuWalkHumanoid25FirstFourSeconds) {
  expect_acceptance("humanoid25", "bvh/cmu_max_131_01_start_walk_stop.bvh", 480);
}
TEST(RefineRealData, Games105WalkTurnG1) { expect_acceptance("g1", "bvh/games105_walk_and_turn_left.bvh"); }
TEST(RefineRealData, BandaiWalkTurnHumanoid25) { expect_acceptance("humanoid25", "bvh/bandai2_walk-turn-left_normal_001.bvh"); }

}  // namespace
}  // namespace rt
