#include "retarget/sim/dynamics_check.hpp"

#include <gtest/gtest.h>

#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// Both controllers hold a standing reference without a violation. The walking controller's plan
// pulls the ZMP to the support's centre (balance_plan.hpp), which leans humanoid25's COM 2.3 cm
// towards the middle of the feet's ankle reach; the paper's stays within 1 cm of the reference COM.
class StandingStill : public ::testing::TestWithParam<CheckControllerKind> {};

TEST_P(StandingStill, Humanoid25ForTenSeconds) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  const Reference ref = constant_reference(*model, model->standing_q(), 10.0, 30.0);
  DynamicsCheckOptions o = default_check_options(*model);
  o.controller = GetParam();
  const DynamicsCheckResult r = run_dynamics_check(*model, ref, o);
  for (const Violation& v : r.violations)
    ADD_FAILURE() << violation_name(v.kind) << " " << v.start_s << "-" << v.end_s << " s: " << v.detail;
  EXPECT_TRUE(r.passed);
  EXPECT_FALSE(r.fell);
  EXPECT_NEAR(r.simulated_s, 10.0, 1e-6);
  EXPECT_LT(r.cop_rms_error_m, 0.01);
  EXPECT_LT(r.com_max_error_m, GetParam() == CheckControllerKind::Paper ? 0.01 : 0.03);
  EXPECT_LT(r.joint_rms_error_rad, 0.02);
  std::cout << "humanoid25 standing (" << check_controller_name(GetParam()) << "): COP error " << r.cop_rms_error_m
            << " m, COM max error " << r.com_max_error_m << " m, joint RMS " << r.joint_rms_error_rad
            << " rad, real-time factor " << r.real_time_factor << "\n";
}

INSTANTIATE_TEST_SUITE_P(Controllers, StandingStill, ::testing::Values(CheckControllerKind::Walking, CheckControllerKind::Paper),
                         [](const ::testing::TestParamInfo<CheckControllerKind>& i) { return check_controller_name(i.param); });

}  // namespace
}  // namespace rt
