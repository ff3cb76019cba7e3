// Walking clips from the shared data (skipped when absent) on humanoid25 and G1: the acceptance
// metrics of issues 4 and 13 after refine + ground (design.md §6 definitions, quality.hpp).

#include <gtest/gtest.h>

#include "refine_test_util.hpp"

namespace rt {
namespace {

void expect_acceptance(const std::string& robot, const std::string& relative, int frames = 0) {
  RT_REQUIRE_SHARED(path, relative);
  const RobotModel& model = test::robot(robot);
  // Measured on the exported frames (30 Hz), as issue 13 states its bars and as the summary reports.
  const test::Converted c = test::convert(model, path, frames, "scale,label-contacts,ik,flat-contact,refine,ground,resample");
  SCOPED_TRACE(robot + " " + relative);
  test::expect_refine_acceptance(c);
  ::testing::Test::RecordProperty("landmark_error_median_m", std::to_string(c.quality.landmark_error_median_m));
}

TEST(RefineRealData, CmuWalkG1) { expect_acceptance("g1", "bvh/cmu_max_131_01_start_walk_stop.bvh"); }
// (The first four seconds of the CMU walk on humanoid25, cut mid-swing, used to be a case here; the
// whole clip on humanoid25 is one of ConvertSharedData's cases, with every bar but swing clearance.)
TEST(RefineRealData, Games105WalkTurnG1) { expect_acceptance("g1", "bvh/games105_walk_and_turn_left.bvh"); }
TEST(RefineRealData, BandaiWalkTurnHumanoid25) { expect_acceptance("humanoid25", "bvh/bandai2_walk-turn-left_normal_001.bvh"); }

}  // namespace
}  // namespace rt
