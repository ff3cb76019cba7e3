// Issue 6 / issue 15: the full pipeline + dynamics check on the real walking clips, for humanoid25
// and G1, with the outcomes pinned so that they cannot change silently (in either direction: a clip
// that starts passing must update this file and the README's table too).
//
// Measured outcome with the walking controller on the default pipeline's references, which com-plan
// has made feasible (their multibody ZMP within 1 cm of the support on every stance frame on G1, and
// on 95-100 % on humanoid25; README, "What the check finds on real clips"): GAMES-105 passes at 1x
// on both robots, the Bandai walk-turn-left and CMU 131_01 at 1x on humanoid25, the Bandai walk at
// 0.96x on G1 (it falls 0.32 s before its end at 1x). Since the re-planner keeps only windows whose
// COP stays on the feet (2026-12-07) humanoid25's CMU walk passes; before, it fell at 4.12 s and
// G1's Bandai walk passed at 0.94x. Until the controller's contact forces kept inside a 0.7 friction
// margin (2026-12-07) G1's Bandai walk passed at 1x and its CMU 131_01 at 0.79x. Before the ZMP
// metric and com-plan's whole-body stage used a compact stencil (2026-12-07), the stage met a ZMP
// whose angular-momentum rate spanned frames f - 2 .. f + 2 and its COM acceleration f - 1 .. f + 1;
// by each body's own second difference 20-50 % of the walks' stance frames were then more than 1 cm
// outside. G1's GAMES-105 fell then, and its CMU walk at every speed. These verdicts still move
// with small changes of the reference.
// G1's CMU walk and PyMO on both robots fail at every speed down to 0.25x (issue 15 is open). So
// what is pinned: GAMES-105 passes at 1x on both robots, Bandai and CMU on humanoid25; G1's Bandai
// walk fails at 1x and --find-speed finds a speed between 0.67x and 1x; every other pair fails at 1x
// with its first failing violation in the first 6 s of the clip, and --find-speed finds no passing
// speed.
// Skips cleanly without ../shared/data.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "retarget/core/strings.hpp"
#include "retarget/jobs/convert_job.hpp"
#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/sim/dynamics_check.hpp"
#include "shared_robots.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

struct Case {
  const char* robot;
  const char* clip;  // relative to the shared data folder
  bool passes = false;  // at 1x
  bool passes_slower = false;  // fails at 1x, --find-speed finds a speed >= 0.67x
};

const char* const kRobots[] = {"humanoid25", "g1"};
const char* const kClips[] = {"bvh/cmu_max_131_01_start_walk_stop.bvh", "bvh/games105_walk_and_turn_left.bvh",
                              "bvh/bandai2_walk-turn-left_normal_001.bvh", "bvh/pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh"};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const char* r : kRobots)
    for (const char* c : kClips) {
      const std::string clip = c;
      const bool bandai = clip == "bvh/bandai2_walk-turn-left_normal_001.bvh";
      const bool games = clip == "bvh/games105_walk_and_turn_left.bvh";
      const bool g1 = std::string(r) == "g1";
      const bool cmu = clip == "bvh/cmu_max_131_01_start_walk_stop.bvh";
      const bool passes = games || ((bandai || cmu) && !g1);
      const bool passes_slower = bandai && g1;
      out.push_back({r, c, passes, passes_slower});
    }
  return out;
}

class WalkingCheck : public ::testing::TestWithParam<Case> {};

TEST_P(WalkingCheck, OutcomeIsPinned) {
  const Case c = GetParam();
  RT_REQUIRE_SHARED(clip, c.clip);
  RT_REQUIRE_SHARED(robots, "robots");
  const RobotModel& model = test::shared_robot(c.robot);
  ConvertRequest convert;
  convert.clip_path = clip;
  convert.write_outputs = false;
  const ConvertResult converted = run_convert(convert, model);
  const Reference& reference = converted.clip.reference;
  ASSERT_GT(reference.num_frames(), 0);
  ASSERT_TRUE(reference.has_contacts());

  ValidateRequest request;
  request.check = default_check_options(model);
  const DynamicsCheckResult at_1x = run_dynamics_check(model, reference, request.check);
  if (c.passes) {
    std::string failing;
    for (const Violation& v : at_1x.violations)
      if (violation_fails_check(v.kind)) failing += format(" %s at %.2f s (%s);", violation_name(v.kind), v.start_s, v.detail.c_str());
    EXPECT_TRUE(at_1x.passed) << "this walk no longer passes the check at 1x:" << failing;
    EXPECT_FALSE(at_1x.fell);
    std::cout << format("[ outcome  ] %-10s %-46s 1x: passes\n", c.robot, c.clip);
    return;
  }
  EXPECT_FALSE(at_1x.passed) << "this walk now passes the check at 1x: update the pinned outcome (test and README)";
  const Violation* first = nullptr;
  for (const Violation& v : at_1x.violations)
    if (violation_fails_check(v.kind) && (!first || v.start_s < first->start_s)) first = &v;
  ASSERT_NE(first, nullptr) << "failed without a failing violation";
  EXPECT_LT(first->start_s, 6.0) << violation_name(first->kind) << ": " << first->detail;
  EXPECT_TRUE(std::isfinite(at_1x.joint_rms_error_rad));

  const SpeedSearchResult speed = find_feasible_speed(reference, model, request);
  EXPECT_FALSE(speed.passes_at_1x);
  ASSERT_FALSE(speed.trials.empty());
  if (c.passes_slower) {
    EXPECT_TRUE(speed.feasible) << "no passing speed any more: update the pinned outcome (test and README)";
    EXPECT_GE(speed.speed, 0.67);
    EXPECT_LT(speed.speed, 1.0);
  } else {
    EXPECT_FALSE(speed.feasible) << "passes at " << speed.speed << "x: update the pinned outcome (test and README)";
    EXPECT_DOUBLE_EQ(speed.trials.back().first, SpeedSearchOptions{}.max_time_scale);  // the slowest was tried
  }

  std::cout << format("[ outcome  ] %-10s %-46s 1x: %s %s at %.2f s (%s); fell %s; %s\n", c.robot, c.clip,
                      at_1x.passed ? "passes" : "fails", violation_name(first->kind), first->start_s, first->detail.c_str(),
                      at_1x.fell ? format("at %.2f s", at_1x.fall_time_s).c_str() : "no",
                      speed.feasible ? format("passes at %.2fx", speed.speed).c_str() : "no passing speed down to 0.25x");
}

INSTANTIATE_TEST_SUITE_P(HumanoidsOnRealWalks, WalkingCheck, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return test::case_name(info.param.robot, info.param.clip); });

// Third-party G1 references that real G1s perform with tracking policies (issue 15's acceptance:
// they should pass at 1x, also with the link masses scaled by 0.9 and 1.1 and the floor friction at
// 0.7). Pinned like the walks: B_HandsUp passes under all four; the others still fall (issue 15 is
// open; README "What the check finds on real clips").
struct ThirdPartyCase {
  const char* csv;  // relative to the shared data folder
  double fps;
  bool passes;
};

class ThirdPartyG1Check : public ::testing::TestWithParam<ThirdPartyCase> {};

TEST_P(ThirdPartyG1Check, OutcomeIsPinned) {
  const ThirdPartyCase c = GetParam();
  RT_REQUIRE_SHARED(csv, c.csv);
  RT_REQUIRE_SHARED(robots, "robots");
  const RobotModel& model = test::shared_robot("g1");
  ValidateRequest request;
  request.reference_path = csv;
  request.fps = c.fps;
  request.check = default_check_options(model);
  if (!c.passes) {
    const ValidateResult r = run_validate(request, model);
    EXPECT_FALSE(r.check.passed) << "this reference now passes the check: update the pinned outcome (test and README)";
    EXPECT_TRUE(r.check.fell);
    std::cout << format("[ outcome  ] g1 %-46s fails, fell at %.2f s\n", c.csv, r.check.fall_time_s);
    return;
  }
  for (const auto& [mass, friction] : {std::pair{1.0, 0.0}, std::pair{0.9, 0.0}, std::pair{1.1, 0.0}, std::pair{1.0, 0.7}}) {
    request.check.mass_scale = mass;
    request.check.floor_friction = friction;
    const ValidateResult r = run_validate(request, model);
    EXPECT_TRUE(r.check.passed) << "masses x" << mass << ", friction " << friction << ": no longer passes";
    EXPECT_FALSE(r.check.fell);
    std::cout << format("[ outcome  ] g1 %-46s masses x%.1f, friction %s: %s\n", c.csv, mass,
                        friction > 0 ? format("%.1f", friction).c_str() : "robot.yaml", r.check.passed ? "passes" : "fails");
  }
}

INSTANTIATE_TEST_SUITE_P(SharedData, ThirdPartyG1Check,
                         ::testing::Values(ThirdPartyCase{"retargeted/g1_moves/B_HandsUp.csv", 60, true},
                                           ThirdPartyCase{"retargeted/g1_moves/J_Dance0_StepTouch.csv", 60, false},
                                           ThirdPartyCase{"retargeted/g1_lafan1_unitree/fight1_subject2.csv", 30, false},
                                           ThirdPartyCase{"retargeted/g1_lafan1_unitree/dance1_subject2.csv", 30, false}),
                         [](const ::testing::TestParamInfo<ThirdPartyCase>& info) { return test::case_name("g1", info.param.csv); });

}  // namespace
}  // namespace rt
