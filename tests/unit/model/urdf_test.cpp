// URDF reading (formats/urdf): the malformed-file folder with expected messages, a valid test robot,
// package:// resolution, console_bridge capture, and the three real robots.

#include <console_bridge/console.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <thread>

#include "formats/urdf/package_uri.hpp"
#include "formats/urdf/urdf_description.hpp"
#include "retarget/core/error.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

std::string broken(const std::string& name) { return test::source_path("tests/data/urdf/broken/" + name); }
std::string mini_urdf() { return test::source_path("tests/data/urdf/mini_biped/mini_biped.urdf"); }
std::vector<std::string> test_packages() { return {test::source_path("tests/data/urdf")}; }

struct BrokenCase {
  const char* file;
  int line;              // expected line in the message, 0 = no line
  const char* message;   // expected text after "<file>:<line>: "
};

// Every file in tests/data/urdf/broken with the exact message it must produce.
const BrokenCase kBrokenCases[] = {
    {"not_xml.urdf", 0, "not an XML document (no element found)"},
    {"empty.urdf", 0, "empty file"},
    {"no_robot.urdf", 2, "not a URDF: the document has no <robot> element"},
    {"no_robot_name.urdf", 2, "invalid URDF: No name given for the robot."},
    {"missing_link.urdf", 4, "joint 'j1' references link 'ghost', which does not exist"},
    {"cycle.urdf", 2, "no root link: every link has a parent joint, so the joints form a cycle"},
    {"cycle_detached.urdf", 10,
     "cycle in the kinematic tree: link 'b' (child of joint 'c_to_b') is not reachable from the root link 'base'"},
    {"two_roots.urdf", 5,
     "two root links: 'base' (line 3) and 'stray' (a link that is not connected to the rest of the tree?)"},
    {"two_parents.urdf", 14, "link 'b' is the child of two joints: 'j2' (line 10) and 'j3'"},
    {"revolute_no_limits.urdf", 5,
     "joint 'elbow' is revolute but has no <limit> (use type continuous for an unlimited revolute joint)"},
    {"negative_mass.urdf", 3, "link 'base' has a negative mass (-2 kg)"},
    {"mass_abc.urdf", 5, "<mass value=\"abc\"> in link 'base': expected a finite number"},
    {"nan_inertia.urdf", 6, "<inertia ixx=\"nan\"> in link 'base': expected a finite number"},
    {"inertial_without_mass.urdf", 4, "<inertial> of link 'base' has no <mass value=...>"},
    {"mesh_without_filename.urdf", 6, "<mesh> without filename in link 'base'"},
    {"planar_joint.urdf", 5,
     "joint 'table' is planar: planar joints are not supported (use revolute, continuous, prismatic, fixed or floating)"},
    {"unknown_joint_type.urdf", 5,
     "joint 'hinge' has unknown type 'ball' (expected revolute, continuous, prismatic, fixed or floating)"},
    {"unsupported_geometry.urdf", 6, "unsupported geometry <capsule> in link 'base' (supported: box, cylinder, sphere, mesh)"},
    {"limits_reversed.urdf", 5, "joint 'elbow' has lower limit 1 > upper limit -1"},
    {"zero_axis.urdf", 5, "joint 'elbow' has a zero or non-finite <axis>"},
    {"duplicate_link.urdf", 4, "duplicate link 'base' (first defined at line 3)"},
    {"bad_origin.urdf", 6, "<origin xyz=\"0 0 oops\"> in joint 'shoulder': expected 3 finite numbers"},
    {"malformed_package_uri.urdf", 5,
     "mesh of link 'base': malformed package URI 'package://only_a_package' (expected package://<package>/<path>)"},
};

TEST(UrdfBroken, EveryFileIsRejectedWithItsMessage) {
  std::set<std::string> covered;
  for (const auto& c : kBrokenCases) {
    SCOPED_TRACE(c.file);
    const std::string path = broken(c.file);
    covered.insert(c.file);
    const std::string where = c.line > 0 ? path + ":" + std::to_string(c.line) : path;
    try {
      read_urdf_file(path);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.location(), where);
      EXPECT_EQ(e.message(), c.message);
    }
  }
  // The folder holds no file without an expectation (except the package cases below).
  for (const auto& entry : std::filesystem::directory_iterator(test::source_path("tests/data/urdf/broken"))) {
    const std::string name = entry.path().filename().string();
    if (name == "missing_mesh.urdf" || name == "bad_package.urdf") continue;
    EXPECT_TRUE(covered.count(name)) << name << " has no expected message";
  }
}

TEST(UrdfBroken, MissingMeshFileNamesTheResolvedPath) {
  const std::string path = broken("missing_mesh.urdf");
  try {
    read_urdf_file(path);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), path + ":5");
    const std::string expected_file =
        std::filesystem::path(test::source_path("tests/data/urdf/broken/meshes/does_not_exist.stl")).lexically_normal().string();
    EXPECT_EQ(e.message(), "mesh of link 'base': file not found: " + expected_file);
  }
}

TEST(UrdfBroken, UnknownPackageIsNamedWithTheSearchPath) {
  const std::string path = broken("bad_package.urdf");
  UrdfReadOptions options;
  options.package_paths = test_packages();
  try {
    read_urdf_file(path, options);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), path + ":5");
    EXPECT_EQ(e.message(), "mesh of link 'base': cannot resolve 'package://no_such_package/meshes/base.stl': package "
                           "'no_such_package' not found in the package search path " + test_packages()[0]);
  }
  // Without any search path the message says so.
  try {
    read_urdf_file(path);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("the package search path is empty"), std::string::npos) << e.what();
  }
  // Missing mesh files can be allowed explicitly (a description without meshes).
  options.require_mesh_files = false;
  const UrdfRobot r = read_urdf_file(path, options);
  EXPECT_EQ(r.links[0].visuals[0].mesh_path, "");
  EXPECT_EQ(r.links[0].visuals[0].mesh_uri, "package://no_such_package/meshes/base.stl");
}

TEST(UrdfBroken, HostileInputsFailFastWithoutCrashing) {
  // Absurd nesting would overflow tinyxml's recursive parser: refused before parsing.
  std::string deep = "<robot name='x'>";
  for (int i = 0; i < 100000; ++i) deep += "<a>";
  for (int i = 0; i < 100000; ++i) deep += "</a>";
  deep += "</robot>";
  try {
    read_urdf_string(deep, "deep.urdf", ".");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "deep.urdf: XML elements nested more than 200 deep: not a URDF");
  }
  // A chain of n links, one joint per line after the first.
  auto chain = [](int n) {
    std::string c = "<robot name='chain'><link name='l0'/>";
    for (int i = 1; i < n; ++i)
      c += "\n<link name='l" + std::to_string(i) + "'/><joint name='j" + std::to_string(i) +
           "' type='continuous'><parent link='l" + std::to_string(i - 1) + "'/><child link='l" + std::to_string(i) +
           "'/><axis xyz='0 0 1'/></joint>";
    return c + "</robot>";
  };
  const UrdfRobot r = read_urdf_string(chain(100), "chain.urdf", ".");
  EXPECT_EQ(r.links.size(), 100u);
  EXPECT_EQ(r.joints[98].type, UrdfJointType::Continuous);
  // Issue 18 item 5: a 20,000-link chain overflowed the MJCF writer's stack; the depth is checked
  // first (in linear time), at the joint of the first link too deep, and the number of links.
  try {
    read_urdf_string(chain(500), "chain.urdf", ".");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "chain.urdf:101: the kinematic tree is more than 100 links deep at link 'l100' "
                                     "(joint 'j100'); a robot is about 10 deep");
  }
  try {
    read_urdf_string(chain(20000), "chain.urdf", ".");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "chain.urdf:1001: more than 1000 links: not a robot this tool can simulate");
  }
  // Issue 18 items 11, 12: 200,000 attributes on one element (quadratic in tinyxml), geometry of
  // 1e300 and a UTF-16 file.
  std::string wide = "<robot name='x'><link name='l0'";
  for (int i = 0; i < 200000; ++i) wide += " a" + std::to_string(i) + "='1'";
  wide += "/></robot>";
  try {
    read_urdf_string(wide, "wide.urdf", ".");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "wide.urdf: an XML element has more than 1000 attributes: not a URDF");
  }
  std::string far = chain(3);
  far.replace(far.find("<axis"), 0, "<origin xyz='1e300 0 0'/>");
  try {
    read_urdf_string(far, "far.urdf", ".");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1e+300 is not between -1000 and 1000"), std::string::npos) << e.what();
  }
  const std::string utf16("\xff\xfe<\0r\0o\0", 8);
  try {
    read_urdf_string(utf16, "wide16.urdf", ".");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("UTF-16"), std::string::npos) << e.what();
  }
  // A multi-byte lead byte followed by ASCII at the end of the text (found by the fuzzer: tinyxml
  // stepped over it by its lead byte and read past the end).
  std::string cut = chain(2);
  cut.replace(cut.rfind("</robot>"), 0, "\n  \xEF<");
  try {
    read_urdf_string(cut, "cut.urdf", ".");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("byte 0xEF at column 3 is not UTF-8"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("cut.urdf:", 0), 0u) << e.what();
  }
}

TEST(UrdfCapture, NothingIsPrintedAndTheHandlerIsRestored) {
  console_bridge::OutputHandler* before = console_bridge::getOutputHandler();
  const console_bridge::LogLevel level_before = console_bridge::getLogLevel();
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  EXPECT_THROW(read_urdf_file(broken("no_robot_name.urdf")), InputError);
  const std::string err = ::testing::internal::GetCapturedStderr();
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(err, "");
  EXPECT_EQ(out, "");
  EXPECT_EQ(console_bridge::getOutputHandler(), before);
  EXPECT_EQ(console_bridge::getLogLevel(), level_before);
}

TEST(UrdfCapture, ConcurrentReadsAreSerialisedAndCorrect) {
  // The console_bridge handler is global: parallel readers must neither crash nor mix messages.
  std::vector<std::thread> threads;
  std::vector<std::string> results(8);
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      try {
        if (t % 2)
          read_urdf_file(broken("no_robot_name.urdf"));
        else
          results[static_cast<std::size_t>(t)] = read_urdf_file(mini_urdf(), {test_packages(), true}).name;
      } catch (const InputError& e) {
        results[static_cast<std::size_t>(t)] = e.message();
      }
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < 8; ++t)
    EXPECT_EQ(results[static_cast<std::size_t>(t)], t % 2 ? "invalid URDF: No name given for the robot." : "mini_biped");
}

TEST(UrdfRead, MiniBipedDescription) {
  UrdfReadOptions options;
  options.package_paths = test_packages();
  const UrdfRobot r = read_urdf_file(mini_urdf(), options);
  EXPECT_EQ(r.name, "mini_biped");
  ASSERT_EQ(r.links.size(), 14u);
  ASSERT_EQ(r.joints.size(), 13u);
  EXPECT_EQ(r.links[static_cast<std::size_t>(r.root_link)].name, "world");
  // Document order, not urdfdom's alphabetical maps.
  EXPECT_EQ(r.links[1].name, "pelvis");
  EXPECT_EQ(r.joints[0].name, "float_base");
  EXPECT_EQ(r.joints[0].type, UrdfJointType::Floating);
  const UrdfLink& pelvis = r.links[static_cast<std::size_t>(r.find_link("pelvis"))];
  std::vector<std::string> children;
  for (int j : pelvis.child_joints) children.push_back(r.joints[static_cast<std::size_t>(j)].name);
  EXPECT_EQ(children, (std::vector<std::string>{"imu_joint", "battery_joint", "waist", "left_hip", "right_hip"}));

  const UrdfJoint& waist = r.joints[static_cast<std::size_t>(r.find_joint("waist"))];
  EXPECT_EQ(waist.type, UrdfJointType::Continuous);
  EXPECT_FALSE(waist.has_position_limits);
  EXPECT_DOUBLE_EQ(waist.effort_limit, 60);
  EXPECT_DOUBLE_EQ(waist.velocity_limit, 5);
  EXPECT_DOUBLE_EQ(waist.damping, 0.5);
  EXPECT_DOUBLE_EQ(waist.friction, 0.2);
  EXPECT_TRUE(waist.X_P_J.translation().isApprox(Vec3(0, 0, 0.07)));

  const UrdfJoint& lift = r.joints[static_cast<std::size_t>(r.find_joint("neck_lift"))];
  EXPECT_EQ(lift.type, UrdfJointType::Prismatic);
  EXPECT_TRUE(lift.has_position_limits);
  EXPECT_DOUBLE_EQ(lift.lower, -0.02);
  EXPECT_DOUBLE_EQ(lift.upper, 0.05);

  // Inertia given with a rotated <origin> is returned in link axes: R I R^T.
  const UrdfLink& battery = r.links[static_cast<std::size_t>(r.find_link("battery"))];
  Mat3 I;
  I << 0.004, 0.0005, -0.0002, 0.0005, 0.002, 0.0001, -0.0002, 0.0001, 0.003;
  const Mat3 R = (AngleAxis(0.5, Vec3::UnitZ()) * AngleAxis(-0.2, Vec3::UnitY()) * AngleAxis(0.3, Vec3::UnitX())).toRotationMatrix();
  EXPECT_TRUE(battery.inertial.I_com.isApprox(R * I * R.transpose(), 1e-12));
  EXPECT_TRUE(battery.inertial.p_L_com.isApprox(Vec3(0.02, 0.01, -0.01)));

  // Geometry kinds, package:// and relative mesh paths, mirrored scale.
  const UrdfLink& torso = r.links[static_cast<std::size_t>(r.find_link("torso"))];
  ASSERT_EQ(torso.collisions.size(), 1u);
  EXPECT_EQ(torso.collisions[0].kind, UrdfGeometry::Kind::Mesh);
  EXPECT_EQ(std::filesystem::path(torso.collisions[0].mesh_path).filename(), "torso.stl");
  EXPECT_TRUE(std::filesystem::exists(torso.collisions[0].mesh_path));
  const UrdfLink& right_arm = r.links[static_cast<std::size_t>(r.find_link("right_upper_arm"))];
  EXPECT_EQ(right_arm.collisions[0].mesh_scale, Vec3(1, -1, 1));
  EXPECT_EQ(std::filesystem::path(right_arm.collisions[0].mesh_path).lexically_normal(),
            std::filesystem::path(test::source_path("tests/data/urdf/mini_biped/meshes/arm.dae")).lexically_normal());
  const UrdfLink& thigh = r.links[static_cast<std::size_t>(r.find_link("left_thigh"))];
  EXPECT_EQ(thigh.collisions[0].kind, UrdfGeometry::Kind::Cylinder);
  EXPECT_DOUBLE_EQ(thigh.collisions[0].radius_m, 0.05);
  EXPECT_DOUBLE_EQ(thigh.collisions[0].length_m, 0.3);
  const UrdfLink& head = r.links[static_cast<std::size_t>(r.find_link("head"))];
  EXPECT_EQ(head.collisions[0].kind, UrdfGeometry::Kind::Sphere);
  EXPECT_EQ(r.link_location(r.find_link("head")), mini_urdf() + ":" + std::to_string(head.line));
}

TEST(PackageUri, ResolutionRules) {
  const std::string root = test::source_path("tests/data/urdf");
  const std::string expected =
      std::filesystem::path(root + "/mini_biped/meshes/torso.stl").lexically_normal().string();
  // <root>/pkg
  EXPECT_EQ(resolve_package_uri("package://mini_biped/meshes/torso.stl", "", {root}).path, expected);
  // <root>/*/pkg (one level down)
  EXPECT_EQ(resolve_package_uri("package://meshes/torso.stl", "", {root}).path, expected);
  // Later roots are searched when earlier ones lack the package.
  EXPECT_EQ(resolve_package_uri("package://mini_biped/meshes/torso.stl", "", {"/nonexistent", root}).path, expected);
  // package:///abs and file:///abs
  EXPECT_EQ(resolve_package_uri("package://" + expected, "", {}).path, expected);
  // package:///pkg/rel (empty authority) is package://pkg/rel, one level down too.
  EXPECT_EQ(resolve_package_uri("package:///mini_biped/meshes/torso.stl", "", {root}).path, expected);
  EXPECT_EQ(resolve_package_uri("package:///meshes/torso.stl", "", {root}).path, expected);
  const auto triple_missing = resolve_package_uri("package:///mini_biped/meshes/nope.stl", "", {root});
  EXPECT_NE(triple_missing.error.find("package 'mini_biped' exists but has no 'meshes/nope.stl'"), std::string::npos)
      << triple_missing.error;
  EXPECT_EQ(resolve_package_uri("file://" + expected, "", {}).path, expected);
  // Relative to the base folder.
  EXPECT_EQ(resolve_package_uri("meshes/torso.stl", root + "/mini_biped", {}).path, expected);
  // Failures carry a reason.
  const auto missing = resolve_package_uri("package://mini_biped/meshes/nope.stl", "", {root});
  EXPECT_EQ(missing.path, "");
  EXPECT_NE(missing.error.find("package 'mini_biped' exists but has no 'meshes/nope.stl'"), std::string::npos) << missing.error;
  EXPECT_NE(resolve_package_uri("http://x/y.stl", "", {}).error.find("unsupported URI scheme"), std::string::npos);
  EXPECT_EQ(split_path_list("/a::/b:"), (std::vector<std::string>{"/a", "/b"}));
}

struct RealRobot {
  const char* urdf;   // relative to the shared data
  const char* package_root;
  std::size_t links, joints, movable;
  double mass_kg;
  const char* root;
};

const RealRobot kRealRobots[] = {
    {"robots/unitree_g1/g1_29dof_rev_1_0.urdf", "robots", 39, 38, 29, 33.3411, "pelvis"},
    {"robots/unitree_h1/h1_description/urdf/h1.urdf", "robots", 25, 24, 19, 59.338, "pelvis"},
    {"robots/jvrc1/jvrc_description/urdf/jvrc1.urdf", "robots", 60, 59, 44, 62.4, "base_link"},
};

TEST(UrdfRead, RealRobotsParse) {
  for (const auto& rr : kRealRobots) {
    SCOPED_TRACE(rr.urdf);
    RT_REQUIRE_SHARED(path, rr.urdf);
    UrdfReadOptions options;
    options.package_paths = {test::shared_data(rr.package_root)};
    const UrdfRobot r = read_urdf_file(path, options);
    EXPECT_EQ(r.links.size(), rr.links);
    EXPECT_EQ(r.joints.size(), rr.joints);
    std::size_t movable = 0;
    double mass = 0;
    for (const auto& j : r.joints) {
      if (j.type == UrdfJointType::Revolute) {
        ++movable;
        EXPECT_TRUE(j.has_position_limits);
        EXPECT_GT(j.effort_limit, 0) << j.name;
        EXPECT_GT(j.velocity_limit, 0) << j.name;
      }
    }
    for (const auto& l : r.links) {
      mass += l.inertial.mass_kg;
      for (const auto* geoms : {&l.collisions, &l.visuals})
        for (const auto& g : *geoms)
          if (g.kind == UrdfGeometry::Kind::Mesh) {
            EXPECT_TRUE(std::filesystem::exists(g.mesh_path)) << g.mesh_uri;
          }
    }
    EXPECT_EQ(movable, rr.movable);
    EXPECT_NEAR(mass, rr.mass_kg, 1e-3);
    EXPECT_EQ(r.links[static_cast<std::size_t>(r.root_link)].name, rr.root);
  }
}

}  // namespace
}  // namespace rt
