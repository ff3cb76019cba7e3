// The project's default robot (issue 2): built from robots/humanoid25, it must have the advertised
// structure and stand for 10 s in the generated MuJoCo model under a simple joint PD.

#include <gtest/gtest.h>

#include <cmath>

#include "retarget/model/robot_model.hpp"
#include "retarget/model/standing_hold.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

TEST(Humanoid25, StructureMatchesTheSpecification) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  EXPECT_EQ(model->nu(), 25);  // legs 2x6, waist 2, neck 1, arms 2x5
  EXPECT_EQ(model->nv(), 31);  // with the floating root
  EXPECT_NEAR(model->total_mass_kg(), 51.0, 1e-9);
  EXPECT_GT(model->standing_com_height_m(), 0.6);
  EXPECT_LT(model->standing_com_height_m(), 1.0);
  for (int i = 0; i < model->nu(); ++i) {
    EXPECT_GT(model->effort_limits()[i], 0);
    EXPECT_GT(model->velocity_limits()[i], 0);
    EXPECT_LT(model->q_lower()[i], model->q_upper()[i]);
  }
}

TEST(Humanoid25, StandsTenSecondsUnderJointPd) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  StandingHoldOptions options;
  options.duration_s = 10.0;
  const StandingHoldResult h = simulate_standing_hold(*model, options);
  EXPECT_FALSE(h.fell) << h.failure;
  EXPECT_FALSE(h.unstable);
  EXPECT_NEAR(h.simulated_s, 10.0, 1e-9);
  EXPECT_NEAR(h.final_root_height_m, h.initial_root_height_m, 0.03);
  EXPECT_LT(h.max_tilt_rad, 3.0 * M_PI / 180) << "max tilt " << h.max_tilt_rad * 180 / M_PI << " deg";
  EXPECT_LT(h.max_com_drift_m, 0.03);
}

}  // namespace
}  // namespace rt
