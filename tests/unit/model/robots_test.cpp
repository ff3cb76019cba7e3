// The project's real-robot configs (G1, H1, JVRC-1; URDFs from the shared data) and the test robot:
// they load, compile into MuJoCo, report sensible mass/COM, and stand for 2 s under the simple PD.
// New robots (robots/<name>/) are covered by adding a row to kRobots.

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "formats/urdf/urdf_description.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/standing_hold.hpp"
#include "model_cache.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

struct RobotCase {
  const char* robot;           // name in robots/ or a path
  bool needs_shared;           // URDF lives in the shared data
  int nu;
  double mass_kg;              // URDF total
  double com_height_min_m, com_height_max_m;  // standing COM height
};

const RobotCase kRobots[] = {
    {"g1", true, 29, 33.3411, 0.60, 0.75},
    {"h1", true, 19, 59.338, 0.85, 1.05},
    {"jvrc1", true, 44, 62.4, 0.75, 0.90},
    {"tests/data/urdf/mini_biped", false, 10, 24.0, 0.6, 0.85},
};

void PrintTo(const RobotCase& c, std::ostream* os) { *os << c.robot; }

std::string robot_arg(const RobotCase& c) {
  return c.needs_shared ? std::string(c.robot) : test::source_path(c.robot);
}

class Robots : public ::testing::TestWithParam<RobotCase> {};

TEST_P(Robots, LoadsWithSensibleMassAndCom) {
  const RobotCase& c = GetParam();
  if (c.needs_shared) {
    RT_REQUIRE_SHARED(robots, "robots");
  }
  const RobotModel* r = &test::cached_robot(robot_arg(c));
  EXPECT_EQ(r->nu(), c.nu);
  EXPECT_EQ(r->mj()->nq, 7 + c.nu);
  EXPECT_EQ(r->mj()->nv, 6 + c.nu);
  EXPECT_EQ(r->mj()->nu, c.nu);
  EXPECT_EQ(r->mj()->jnt_type[0], mjJNT_FREE);
  EXPECT_NEAR(r->total_mass_kg(), c.mass_kg, 1e-3);

  // MuJoCo's mass equals the URDF sum (no massless moving bodies in these robots).
  UrdfReadOptions options;
  options.package_paths = r->config().package_paths;
  const UrdfRobot urdf = read_urdf_file(r->config().urdf_path, options);
  double urdf_mass = 0;
  for (const auto& l : urdf.links) urdf_mass += l.inertial.mass_kg;
  EXPECT_NEAR(mj_getTotalmass(r->mj()), urdf_mass, 1e-9);
  EXPECT_NEAR(r->total_mass_kg(), urdf_mass, 1e-9);

  // Standing: soles on the floor, COM between the feet and at a plausible height.
  RobotData data(*r);
  update_kinematics(*r, data, r->standing_q());
  double lowest = 1e9, highest = -1e9;
  Vec3 sole_mid = Vec3::Zero();
  for (const Sole& s : r->soles()) {
    for (const Vec3& p : s.corners_L()) {
      const Vec3 w = link_point(*r, data, s.link, p);
      lowest = std::min(lowest, w.z());
      highest = std::max(highest, w.z());
    }
    sole_mid += 0.5 * link_point(*r, data, s.link, s.p_L_center);
  }
  EXPECT_NEAR(lowest, 0, 1e-9);
  EXPECT_LT(highest, 0.005);  // both soles flat on the floor
  const Vec3 com = com_position(*r, data);
  EXPECT_NEAR(com.z(), r->standing_com_height_m(), 1e-12);
  EXPECT_GT(com.z(), c.com_height_min_m);
  EXPECT_LT(com.z(), c.com_height_max_m);
  EXPECT_LT((com.head<2>() - sole_mid.head<2>()).norm(), 0.05) << "COM not above the feet";
  // Every configured landmark resolves to a link.
  for (const auto& lm : r->config().landmarks) EXPECT_GE(r->find_link(lm.link), 0) << lm.link;
  // Export order is a permutation of the movable joints.
  std::vector<int> order = r->export_joint_order();
  std::sort(order.begin(), order.end());
  for (int k = 0; k < r->nu(); ++k) EXPECT_EQ(order[static_cast<std::size_t>(k)], k);
}

TEST_P(Robots, StandsTwoSecondsUnderJointPd) {
  const RobotCase& c = GetParam();
  if (c.needs_shared) {
    RT_REQUIRE_SHARED(robots, "robots");
  }
  const RobotModel* r = &test::cached_robot(robot_arg(c));
  StandingHoldOptions options;
  options.duration_s = 2.0;
  const StandingHoldResult h = simulate_standing_hold(*r, options);
  EXPECT_FALSE(h.fell) << h.failure;
  EXPECT_FALSE(h.unstable);
  EXPECT_NEAR(h.simulated_s, 2.0, 1e-9);
  EXPECT_NEAR(h.final_root_height_m, h.initial_root_height_m, 0.03);
  EXPECT_GT(h.min_root_height_m, h.initial_root_height_m - 0.03);
  EXPECT_LT(h.max_tilt_rad, 5.0 * M_PI / 180) << "max tilt " << h.max_tilt_rad * 180 / M_PI << " deg";
  EXPECT_LT(h.max_com_drift_m, 0.05);
  EXPECT_LT(h.final_max_joint_error, 0.05);
}

INSTANTIATE_TEST_SUITE_P(All, Robots, ::testing::ValuesIn(kRobots),
                         [](const ::testing::TestParamInfo<RobotCase>& info) {
                           std::string n = base_name(info.param.robot);
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

TEST(StandingHold, DetectsAFall) {
  // Without joint torques the test robot collapses: a non-sole geom reaches the floor or the COM
  // drops, and the run stops there.
  const RobotModel* r = &test::cached_robot(test::source_path("tests/data/urdf/mini_biped"));
  StandingHoldOptions options;
  options.kp = 0;
  options.kd = 0;
  options.duration_s = 5;
  const StandingHoldResult h = simulate_standing_hold(*r, options);
  EXPECT_TRUE(h.fell);
  EXPECT_FALSE(h.failure.empty());
  EXPECT_LT(h.simulated_s, 5.0);
  EXPECT_EQ(h.steps, static_cast<int>(std::lround(h.simulated_s / r->mj()->opt.timestep)));
}

TEST(RealData, G1ExportOrderMatchesUnitreeLafanCsv) {
  // Unitree's LAFAN1 retargeting CSV uses the G1 URDF joint order; in our export order every
  // frame's joint values lie inside the URDF limits (a shuffled order would not).
  RT_REQUIRE_SHARED(csv, "retargeted/g1_lafan1_unitree/fight1_subject2.csv");
  const RobotModel* r = &test::cached_robot("g1");
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  while (rows < 2000 && std::getline(in, line)) {
    const auto cells = split(line, ",");
    ASSERT_EQ(cells.size(), 7u + 29u);
    for (int k = 0; k < r->nu(); ++k) {
      const int model_index = r->export_joint_order()[static_cast<std::size_t>(k)];
      const double value = std::stod(cells[7 + static_cast<std::size_t>(k)]);
      EXPECT_GE(value, r->q_lower()[model_index] - 1e-3) << "row " << rows << " column " << k;
      EXPECT_LE(value, r->q_upper()[model_index] + 1e-3) << "row " << rows << " column " << k;
    }
    ++rows;
  }
  EXPECT_EQ(rows, 2000);
}

}  // namespace
}  // namespace rt
