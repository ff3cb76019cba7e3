#include "retarget/sim/dynamics_check.hpp"

#include <gtest/gtest.h>

#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

TEST(DynamicsCheck, Humanoid25StandsStillForTenSeconds) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  const Reference ref = constant_reference(*model, model->standing_q(), 10.0, 30.0);
  const DynamicsCheckResult r = run_dynamics_check(*model, ref, default_check_options(*model));
  for (const Violation& v : r.violations)
    ADD_FAILURE() << violation_name(v.kind) << " " << v.start_s << "-" << v.end_s << " s: " << v.detail;
  EXPECT_TRUE(r.passed);
  EXPECT_FALSE(r.fell);
  EXPECT_NEAR(r.simulated_s, 10.0, 1e-6);
  EXPECT_LT(r.cop_rms_error_m, 0.01);
  EXPECT_LT(r.com_max_error_m, 0.01);
  EXPECT_LT(r.joint_rms_error_rad, 0.02);
  std::cout << "humanoid25 standing: COP error " << r.cop_rms_error_m << " m, COM max error " << r.com_max_error_m
            << " m, joint RMS " << r.joint_rms_error_rad << " rad, real-time factor " << r.real_time_factor << "\n";
}

}  // namespace
}  // namespace rt
