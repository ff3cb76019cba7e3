// The part of each sole where the ankle's effort limits can hold the COP (ankle_reach.hpp).

#include "retarget/model/ankle_reach.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// G1: ankle pitch 35 N m under its weight reaches about 10 cm from the axis, which lies 3.8 cm
// behind the sole centre: the front of the 0.20 m sole is cut, the back and the width are not.
TEST(AnkleReach, G1AnklePitchCutsTheToe) {
  if (test::shared_data("robots").empty()) GTEST_SKIP() << "shared robot data absent";
  const auto model = RobotModel::load(test::source_path("robots/g1"));
  const double weight = model->total_mass_kg() * 9.81;
  const auto reach = ankle_reach(*model, weight);
  for (int f = 0; f < 2; ++f) {
    const SoleReach& r = reach[static_cast<std::size_t>(f)];
    const Sole& sole = model->soles()[static_cast<std::size_t>(f)];
    std::cout << "[ reach    ] foot " << f << ": x " << r.min_S.x() << ".." << r.max_S.x() << ", y " << r.min_S.y() << ".."
              << r.max_S.y() << " (" << r.pitch_joint << ", " << r.roll_joint << ")\n";
    EXPECT_NE(r.pitch_joint.find("ankle_pitch"), std::string::npos);
    EXPECT_NE(r.roll_joint.find("ankle_roll"), std::string::npos);
    EXPECT_NEAR(r.max_S.x(), 35.0 / weight - 0.038, 0.01);
    EXPECT_DOUBLE_EQ(r.min_S.x(), -0.5 * sole.size_m.x());
    EXPECT_DOUBLE_EQ(r.min_S.y(), -0.5 * sole.size_m.y());
    EXPECT_DOUBLE_EQ(r.max_S.y(), 0.5 * sole.size_m.y());
  }
  // A light load leaves the whole sole; an enormous one only the line under the axes.
  const auto light = ankle_reach(*model, 10.0);
  EXPECT_DOUBLE_EQ(light[0].max_S.x(), 0.5 * model->soles()[0].size_m.x());
  const auto heavy = ankle_reach(*model, 1e9);
  EXPECT_NEAR(heavy[0].max_S.x() - heavy[0].min_S.x(), 0.0, 1e-6);
  EXPECT_NEAR(heavy[0].max_S.x(), -0.038, 0.01);
}

TEST(AnkleReach, CornersAreTheRegionAtTheSoleFrame) {
  SoleReach r;
  r.min_S = Vec2(-0.1, -0.04);
  r.max_S = Vec2(0.06, 0.04);
  Iso3 X = Iso3::Identity();
  X.translation() = Vec3(1, 2, 0);
  X.linear() = AngleAxis(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  const auto c = reach_corners_W(X, r);
  EXPECT_TRUE(c[0].isApprox(Vec3(1 - 0.04, 2 + 0.06, 0)));  // front left: x forward is +y in W
  EXPECT_TRUE(c[2].isApprox(Vec3(1 + 0.04, 2 - 0.1, 0)));   // back right
}

}  // namespace
}  // namespace rt
