// Issue 6: the project's slow-steps example (with the paper's controller, `--controller paper`) (four slow steps, the weight shifted over the stance
// foot before every lift) through the default pipeline and the dynamics check, on humanoid25 and G1.
// With dynamic mapping (the default) it passes on both. Since the refine pass holds the stance soles
// flat and fixed on every frame (issue 13), humanoid25 passes without dynamic mapping too (before,
// it could not lift its right foot off at 7.7 s); G1 without it falls at 11.1 s at 1x and after
// about 5 s at 1.1x-1.5x slower (not pinned here: README "What the check finds on real clips").
// G1 skips cleanly without ../shared/data.

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "retarget/jobs/convert_job.hpp"
#include "retarget/jobs/validate_job.hpp"
#include "retarget/sim/dynamics_check.hpp"
#include "retarget/sim/violations.hpp"
#include "shared_robots.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// The converted example on `robot` (converted once per robot and test program); empty when the
// robot's shared data is absent.
const Reference& slow_steps_reference(const std::string& robot) {
  static std::map<std::string, Reference> cache;
  auto it = cache.find(robot);
  if (it == cache.end()) {
    Reference r;
    if (robot == "humanoid25" || !test::shared_data("robots").empty()) {
      ConvertRequest convert;
      convert.clip_path = test::source_path("examples/clips/slow_steps.bvh");
      convert.write_outputs = false;
      r = run_convert(convert, test::shared_robot(robot)).clip.reference;
    }
    it = cache.emplace(robot, std::move(r)).first;
  }
  return it->second;
}

DynamicsCheckResult check_slow_steps(const std::string& robot, bool dynamic_mapping,
                                     CheckControllerKind controller = CheckControllerKind::Paper) {
  const RobotModel& model = test::shared_robot(robot);
  DynamicsCheckOptions o = default_check_options(model);
  o.controller = controller;
  o.dynamic_mapping = dynamic_mapping;
  return run_dynamics_check(model, slow_steps_reference(robot), o);
}

std::string failing(const DynamicsCheckResult& r) {
  std::string s;
  for (const Violation& v : r.violations)
    if (violation_fails_check(v.kind)) s += std::string(violation_name(v.kind)) + " at " + std::to_string(v.start_s) + " s: " + v.detail + "; ";
  return s;
}

class SlowSteps : public ::testing::TestWithParam<const char*> {};

TEST_P(SlowSteps, PassesWithDynamicMapping) {
  if (slow_steps_reference(GetParam()).num_frames() == 0) GTEST_SKIP() << "shared robot data absent";
  const DynamicsCheckResult r = check_slow_steps(GetParam(), true);
  EXPECT_TRUE(r.passed) << failing(r);
  EXPECT_FALSE(r.fell);
  EXPECT_NEAR(r.simulated_s, r.clip_duration_s, 0.01);
  EXPECT_GT(r.replans.size(), 0u);  // the re-planner is active
  EXPECT_LT(r.com_rms_error_m, 0.05);
}

// Issue 15: the walking controller (the default) passes them too.
TEST_P(SlowSteps, PassesWithTheWalkingController) {
  if (slow_steps_reference(GetParam()).num_frames() == 0) GTEST_SKIP() << "shared robot data absent";
  const DynamicsCheckResult r = check_slow_steps(GetParam(), true, CheckControllerKind::Walking);
  EXPECT_TRUE(r.passed) << failing(r);
  EXPECT_NEAR(r.simulated_s, r.clip_duration_s, 0.01);
  EXPECT_TRUE(r.walking.used);
  EXPECT_LT(r.walking.plan_max_shift_m, 0.08);
}

TEST(SlowStepsHumanoid25, WithoutDynamicMappingItPassesToo) {
  const DynamicsCheckResult r = check_slow_steps("humanoid25", false);
  EXPECT_TRUE(r.passed) << "slow steps no longer pass without dynamic mapping: update the pinned outcome (test and README): "
                        << failing(r);
  EXPECT_TRUE(r.replans.empty());
  EXPECT_NEAR(r.simulated_s, r.clip_duration_s, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Robots, SlowSteps, ::testing::Values("humanoid25", "g1"));

}  // namespace
}  // namespace rt
