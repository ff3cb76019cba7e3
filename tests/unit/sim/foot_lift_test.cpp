// The paper's foot-lift experiment (§VII-A, Fig. 7) as tests: a reference that lifts the right foot
// for t in [1, 2) s without shifting the COM. Without dynamic mapping the robot cannot lift the foot
// (or falls); with it the COM reference moves about 0.5 s before the lift, the COP first moves
// towards the right foot, then reaches the left sole before t = 1 s, the right foot's load goes to
// zero and the robot stays up.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/synthetic_references.hpp"
#include "retarget/sim/dynamics_check.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

struct Robot {
  const char* name;
  const char* required_shared;  // "" when the robot is the project's own
};

class FootLift : public ::testing::TestWithParam<Robot> {
 protected:
  std::unique_ptr<RobotModel> load() {
    const Robot r = GetParam();
    if (*r.required_shared && test::shared_data(r.required_shared).empty())
      return nullptr;
    return RobotModel::load(test::source_path(std::string("robots/") + r.name));
  }
};

// Left sole's extent along y (it does not move: the left foot stays down).
std::pair<double, double> left_sole_y(const RobotModel& model) {
  RobotData data(model);
  update_kinematics(model, data, model.standing_q());
  const Sole& s = model.soles()[0];
  const Iso3 X = link_pose(model, data, s.link);
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec3& c : s.corners_L()) {
    lo = std::min(lo, (X * c).y());
    hi = std::max(hi, (X * c).y());
  }
  return {lo, hi};
}

TEST_P(FootLift, WithoutDynamicMappingTheFootCannotLiftSafely) {
  const auto model = load();
  if (!model) GTEST_SKIP() << "shared robot data absent";
  DynamicsCheckOptions o = default_check_options(*model);
  o.controller = CheckControllerKind::Paper;  // the paper's Fig. 7 ablation
  o.dynamic_mapping = false;
  const DynamicsCheckResult r = run_dynamics_check(*model, foot_lift_reference(*model), o);
  EXPECT_FALSE(r.passed);
  const bool fell_or_stuck = r.fell || std::any_of(r.violations.begin(), r.violations.end(), [](const Violation& v) {
                               return v.kind == ViolationKind::LiftOffNotAchieved;
                             });
  EXPECT_TRUE(fell_or_stuck);
  EXPECT_TRUE(r.replans.empty());
}

TEST_P(FootLift, WithDynamicMappingReproducesFigure7) {
  const auto model = load();
  if (!model) GTEST_SKIP() << "shared robot data absent";
  DynamicsCheckOptions o = default_check_options(*model);
  o.controller = CheckControllerKind::Paper;  // the paper's Fig. 7
  const DynamicsCheckResult r = run_dynamics_check(*model, foot_lift_reference(*model), o);
  for (const Violation& v : r.violations)
    if (violation_fails_check(v.kind)) ADD_FAILURE() << violation_name(v.kind) << " at " << v.start_s << " s: " << v.detail;
  EXPECT_TRUE(r.passed);
  EXPECT_FALSE(r.fell);

  // The reference COM is modified about 0.5 s before the lift (N = 100 steps of 5 ms).
  ASSERT_FALSE(r.replans.empty());
  EXPECT_NEAR(r.replans.front().t_s, 0.5, 0.05);

  const DynamicsTrace& tr = r.trace;
  const auto [sole_lo, sole_hi] = left_sole_y(*model);
  double min_cop_before = INFINITY, t_reached = -1;
  for (std::size_t i = 0; i < tr.t_s.size(); ++i) {
    const double t = tr.t_s[i], y = tr.cop_W[i].y();
    if (t > 0.5 && t < 1.0 && std::isfinite(y)) min_cop_before = std::min(min_cop_before, y);
    if (t_reached < 0 && std::isfinite(y) && y >= sole_lo - 0.002) t_reached = t;
  }
  // The COP first moves towards the right foot (negative y), pushing the COM left ...
  EXPECT_LT(min_cop_before, -0.005);
  // ... then reaches the left sole before the lift.
  EXPECT_GT(t_reached, 0.5);
  EXPECT_LT(t_reached, 1.0 + 1e-9);
  // The right foot lifts: no load during the middle of the lift.
  for (std::size_t i = 0; i < tr.t_s.size(); ++i) {
    if (tr.t_s[i] > 1.2 && tr.t_s[i] < 1.8) {
      EXPECT_LT(tr.foot_force_n[i][1], 1.0) << "t = " << tr.t_s[i];
    }
  }
  // The actual COM ends up over the left sole while the right foot is up.
  for (std::size_t i = 0; i < tr.t_s.size(); ++i)
    if (std::abs(tr.t_s[i] - 1.5) < 1e-6) {
      EXPECT_GT(tr.com_W[i].y(), sole_lo - 0.01);
      EXPECT_LT(tr.com_W[i].y(), sole_hi);
    }
}

INSTANTIATE_TEST_SUITE_P(Robots, FootLift,
                         ::testing::Values(Robot{"humanoid25", ""}, Robot{"g1", "robots/unitree_g1/g1_29dof_rev_1_0.urdf"}),
                         [](const ::testing::TestParamInfo<Robot>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace rt
