// robot.yaml: schema errors with file:line and key path, lookups, and errors found against the URDF
// (unknown links and joints) reported at their robot.yaml location.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "retarget/core/error.hpp"
#include "retarget/model/robot_config.hpp"
#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"
#include "support/text_mutation.hpp"

namespace rt {
namespace {

// Configs are parsed as if they were tests/data/urdf/mini_biped/<name>, so that `urdf:` and
// `package_paths:` resolve against the test robot's folder.
std::string fake_path(const std::string& name = "test.yaml") {
  return std::filesystem::path(test::source_path("tests/data/urdf/mini_biped/" + name)).lexically_normal().string();
}

const char* kBase = R"(name: t
urdf: mini_biped.urdf
package_paths: [..]
feet:
  left:  {link: left_foot, sole: derive}
  right: {link: right_foot, sole: derive}
)";

// Expects parse_robot_config(text) to fail with exactly "<fake_path>:<line>: <message>".
void expect_config_error(const std::string& text, int line, const std::string& message) {
  try {
    parse_robot_config(text, fake_path());
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), fake_path() + ":" + std::to_string(line) + ": " + message) << text;
  }
}

// Expects RobotModel::load(parse_robot_config(text)) to fail the same way (URDF cross-checks).
void expect_model_error(const std::string& text, int line, const std::string& message) {
  try {
    RobotModel::load(parse_robot_config(text, fake_path()));
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), fake_path() + ":" + std::to_string(line) + ": " + message) << text;
  }
}

TEST(RobotConfig, MiniBipedConfigValues) {
  const std::string path = test::source_path("tests/data/urdf/mini_biped/robot.yaml");
  const RobotConfig c = load_robot_config(path, {"/extra/first"});
  EXPECT_EQ(c.name, "mini_biped");
  EXPECT_EQ(c.urdf_path, std::filesystem::path(test::source_path("tests/data/urdf/mini_biped/mini_biped.urdf")).lexically_normal().string());
  ASSERT_GE(c.package_paths.size(), 2u);
  EXPECT_EQ(c.package_paths[0], "/extra/first");  // --package-path comes first
  EXPECT_EQ(c.package_paths[1], std::filesystem::path(test::source_path("tests/data/urdf")).lexically_normal().string());
  EXPECT_EQ(c.feet[kLeftFoot].link, "left_foot");
  EXPECT_TRUE(c.feet[kLeftFoot].sole.derive);
  EXPECT_FALSE(c.feet[kRightFoot].sole.derive);
  EXPECT_EQ(c.feet[kRightFoot].sole.p_L_center, Vec3(0.03, 0.0, -0.06));
  EXPECT_EQ(c.feet[kRightFoot].sole.size_m, Vec2(0.22, 0.1));
  ASSERT_EQ(c.landmarks.size(), 8u);
  EXPECT_EQ(c.landmarks[0].landmark, Landmark::Pelvis);
  EXPECT_DOUBLE_EQ(c.landmarks[0].orientation_weight, 1.0);
  EXPECT_EQ(c.landmarks[1].p_L_offset, Vec3(0, 0, 0.3));
  EXPECT_EQ(c.landmarks[4].landmark, Landmark::RightKnee);  // scalar shorthand: just the link
  EXPECT_EQ(c.landmarks[4].link, "right_shank");
  EXPECT_DOUBLE_EQ(c.landmarks[7].weight, 0.5);
  EXPECT_DOUBLE_EQ(c.standing_joints.at("left_knee"), 0.4);
  EXPECT_FALSE(c.standing_root_height_m.has_value());
  EXPECT_DOUBLE_EQ(c.simulation.armature, 0.02);
  EXPECT_DOUBLE_EQ(c.simulation.joint_armature.at("waist"), 0.05);
  EXPECT_DOUBLE_EQ(c.simulation.extra_damping, 0.1);
  EXPECT_DOUBLE_EQ(c.simulation.hold_kp, 400);
  EXPECT_DOUBLE_EQ(c.controller.kp, 36);  // default
  EXPECT_EQ(c.where("feet.right.sole"), path + ":8");
  EXPECT_EQ(c.where("standing_pose.joints.left_knee"), path + ":19");
  EXPECT_EQ(c.where("no.such.key"), path);
}

TEST(RobotConfig, SchemaErrorsNameFileLineAndKeyPath) {
  ::unsetenv("ROS_PACKAGE_PATH");  // the expected messages list the search path
  const std::string base = kBase;
  expect_config_error(base + "feat: 1\n", 7,
                      "feat: unknown key (allowed: name, urdf, package_paths, feet, landmarks, base_orientation, joint_limits, export_joints, "
                      "npz_layout, standing_pose, controller, simulation)");
  expect_config_error(base + "npz_layout: isaac\n", 7, "npz_layout: expected urdf, mjcf:FILE or names:FILE, got 'isaac'");
  try {
    parse_robot_config(base + "npz_layout: mjcf:no_such.xml\n", fake_path());
    ADD_FAILURE() << "a missing layout file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":7: npz_layout: mjcf file not found"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parse_robot_config(base + "npz_layout: names:mini_biped.urdf\n", fake_path()).npz_layout,
            "names:" + fake_path("mini_biped.urdf"));
  expect_config_error("name: t\nurdf: mini_biped.urdf\nfeet:\n  left: {lnk: left_foot, sole: derive}\n", 4,
                      "feet.left.lnk: unknown key (allowed: link, sole)");
  expect_config_error(base + "landmarks:\n  pelvis: {link: pelvis, weight: abc}\n", 8,
                      "landmarks.pelvis.weight: expected a number, got 'abc'");
  expect_config_error(base + "landmarks:\n  left_foot: {link: left_foot}\n", 8,
                      "landmarks.left_foot: unknown landmark 'left_foot' (known: pelvis, spine, chest, neck, head, "
                      "left_hip, left_knee, left_ankle, left_toe, left_heel, left_shoulder, left_elbow, left_wrist, "
                      "left_hand, right_hip, right_knee, right_ankle, right_toe, right_heel, right_shoulder, "
                      "right_elbow, right_wrist, right_hand)");
  expect_config_error(base + "landmarks:\n  left_knee: {link: left_shank, orientation_weight: 1}\n", 8,
                      "landmarks.left_knee.orientation_weight: landmark 'left_knee' carries no orientation (only "
                      "pelvis, chest, left_ankle and right_ankle do)");
  // Issue 18 item 12: offsets of 1e300 m ran the check.
  expect_config_error(base + "landmarks:\n  pelvis: {link: pelvis, offset: [0, 1e300, 0]}\n", 8,
                      "landmarks.pelvis.offset: 1e+300 m is not between -100 and 100 m");
  expect_config_error(base + "landmarks:\n  pelvis: {link: pelvis, weight: -1}\n", 8,
                      "landmarks.pelvis.weight: weight must be in [0, 1e+06], got -1");
  expect_config_error(base + "landmarks:\n  pelvis: {link: pelvis, offset: [0, 0]}\n", 8,
                      "landmarks.pelvis.offset: expected a list of 3 numbers, got 2");
  expect_config_error("name: t\nurdf: mini_biped.urdf\nfeet:\n  left: {link: left_foot, sole: derived}\n"
                      "  right: {link: right_foot, sole: derive}\n",
                      4, "feet.left.sole: expected 'derive' or a map {center: [x, y, z], size: [length, width]}");
  expect_config_error("name: t\nurdf: mini_biped.urdf\nfeet:\n  left: {link: left_foot, sole: {center: [0, 0, 0], "
                      "size: [0.2, -0.1]}}\n  right: {link: right_foot, sole: derive}\n",
                      4, "feet.left.sole.size: sole length and width must be positive");
  expect_config_error("name: t\nurdf: mini_biped.urdf\nfeet:\n  left: {link: left_foot, sole: derive}\n", 4,
                      "feet: missing required key 'right'");
  expect_config_error("name: t\nurdf: mini_biped.urdf\nfeet:\n  left: {link: foot, sole: derive}\n"
                      "  right: {link: foot, sole: derive}\n",
                      5, "feet.right.link: left and right feet use the same link");
  expect_config_error(base + "simulation: {timestep: 0.5}\n", 7, "simulation.timestep: timestep must be in [1e-05, 0.05], got 0.5");
  expect_config_error(base + "simulation: {armature: [1]}\n", 7, "simulation.armature: expected a number");
  expect_config_error(base + "controller: {kp: 1, gains: 2}\n", 7, "controller.gains: unknown key (allowed: kp, kd, group_gains, joint_gains, foot_gains)");
  expect_config_error(base + "controller: {foot_gains: {kd: 3}}\n", 7, "controller.foot_gains: missing required key 'kp'");
  expect_config_error(base + "export_joints: [waist, waist]\n", 7, "export_joints[1]: joint 'waist' is listed twice");
  expect_config_error(base + "standing_pose: {root_height: -1}\n", 7,
                      "standing_pose.root_height: root_height must be in [0.001, 100], got -1");
  expect_config_error("urdf: mini_biped.urdf\n", 1, "missing required key 'name'");
  expect_config_error("name: t\nurdf: nope.urdf\n", 2,
                      "urdf: URDF not found: file not found: " + fake_path("nope.urdf") + " (add its folder with --package-path)");
  expect_config_error("name: t\nurdf: package://no_pkg/x.urdf\npackage_paths: [..]\n", 2,
                      "urdf: URDF not found: cannot resolve 'package://no_pkg/x.urdf': package 'no_pkg' not found in the package "
                      "search path " + std::filesystem::path(test::source_path("tests/data/urdf")).lexically_normal().string() +
                          " (add its folder with --package-path)");
  expect_config_error("- a\n- b\n", 1, "expected a map of keys");
}

TEST(RobotConfig, UnknownLinksAndJointsAreReportedAtTheirYamlLine) {
  const std::string base = kBase;
  expect_model_error("name: t\nurdf: mini_biped.urdf\npackage_paths: [..]\nfeet:\n  left:  {link: left_fot, sole: derive}\n"
                     "  right: {link: right_foot, sole: derive}\n",
                     5, "feet.left.link: unknown link 'left_fot' (not in mini_biped.urdf)");
  expect_model_error(base + "landmarks:\n  head: {link: skull}\n", 8,
                     "landmarks.head.link: unknown link 'skull' (not in mini_biped.urdf)");
  expect_model_error(base + "landmarks:\n  pelvis: world\n", 8,
                     "landmarks.pelvis.link: link 'world' is the empty world link above the floating joint");
  expect_model_error(base + "standing_pose:\n  joints: {left_knee: 0.3, left_knees: 0.2}\n", 8,
                     "standing_pose.joints.left_knees: unknown joint 'left_knees' (not in mini_biped.urdf)");
  expect_model_error(base + "standing_pose:\n  joints: {left_knee: 3.0}\n", 8,
                     "standing_pose.joints.left_knee: 3 is outside the joint range [0, 2.4]");
  expect_model_error(base + "standing_pose:\n  joints: {imu_joint: 0.1}\n", 8,
                     "standing_pose.joints.imu_joint: joint 'imu_joint' is not a movable (revolute, continuous or "
                     "prismatic) joint");
  expect_model_error(base + "simulation:\n  joint_armature: {elbow: 0.1}\n", 8,
                     "simulation.joint_armature.elbow: unknown joint 'elbow' (not in mini_biped.urdf)");
  expect_model_error(base + "controller:\n  joint_gains:\n    knee: {kp: 1}\n", 9,
                     "controller.joint_gains.knee: unknown joint 'knee' (not in mini_biped.urdf)");
  expect_model_error(base + "export_joints: [waist, neck_lift, left_shoulder, nope]\n", 7,
                     "export_joints[3]: unknown joint 'nope' (not in mini_biped.urdf)");
  expect_model_error(base + "export_joints: [waist, neck_lift]\n", 7,
                     "export_joints: must list every movable joint; missing: left_shoulder, right_shoulder, left_hip, "
                     "left_knee, left_ankle, right_hip, right_knee, right_ankle");
  // A foot link without collision geometry cannot derive its sole.
  expect_model_error("name: t\nurdf: mini_biped.urdf\npackage_paths: [..]\nfeet:\n  left:  {link: imu, sole: derive}\n"
                     "  right: {link: right_foot, sole: derive}\n",
                     5, "feet.left.sole: cannot derive the sole: link 'imu' has no collision or visual geometry (give {center: "
                        "[x, y, z], size: [length, width]})");
}

TEST(RobotConfig, LookupByNameFolderAndFile) {
  // A folder holding robot.yaml, or the file itself.
  const std::string folder = test::source_path("tests/data/urdf/mini_biped");
  EXPECT_EQ(load_robot_config(folder).name, "mini_biped");
  // A bare name along $RETARGET_ROBOTS_PATH.
  const char* old = std::getenv("RETARGET_ROBOTS_PATH");
  const std::string saved = old ? old : "";
  ::setenv("RETARGET_ROBOTS_PATH", test::source_path("tests/data/urdf").c_str(), 1);
  EXPECT_EQ(load_robot_config("mini_biped").name, "mini_biped");
  EXPECT_EQ(robot_search_path().front(), test::source_path("tests/data/urdf"));
  EXPECT_EQ(robot_search_path().back(), test::source_path("robots"));
  try {
    load_robot_config("no_such_robot");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), "no_such_robot");
    EXPECT_NE(e.message().find("robot not found"), std::string::npos);
  }
  if (old)
    ::setenv("RETARGET_ROBOTS_PATH", saved.c_str(), 1);
  else
    ::unsetenv("RETARGET_ROBOTS_PATH");
}

TEST(RobotConfig, ProjectRobotConfigsParse) {
  for (const char* name : {"g1", "h1", "jvrc1"}) {
    SCOPED_TRACE(name);
    RT_REQUIRE_SHARED(robots, "robots");
    const RobotConfig c = load_robot_config(name);
    EXPECT_EQ(c.name, name);
    EXPECT_TRUE(std::filesystem::exists(c.urdf_path));
    EXPECT_GE(c.landmarks.size(), 20u);
    int oriented = 0;
    for (const auto& l : c.landmarks) oriented += l.orientation_weight > 0;
    EXPECT_EQ(oriented, 4);  // pelvis, chest and both feet
    EXPECT_FALSE(c.export_joints.empty());
    EXPECT_FALSE(c.standing_joints.empty());
  }
}

// Issue 18: seeded mutants of a robot.yaml parse or raise one one-line InputError.
TEST(RobotConfig, MutatedConfigsAreLocatedErrorsOrParse) {
  const std::string seed = std::string(kBase) +
                           "landmarks:\n  pelvis: {link: pelvis, offset: [0, 0, -0.1], weight: 1.0}\n"
                           "  left_knee: left_shank\nstanding_pose: {joints: {}}\ncontroller: {kp: 36, kd: 12}\n";
  const int rejected = test::fuzz_text(seed, ":{}[],- \n#'\"0123456789e.", 18, 1500, std::chrono::milliseconds(2000),
                                       [](const std::string& text) { parse_robot_config(text, fake_path()); });
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace rt
