// Onboarding an unconventional URDF (tests/data/urdf/odd_biped): soles derived from the lowest face
// in the standing pose for any foot-link orientation, package:/// URIs, Y_UP COLLADA meshes in mm,
// omitted standing joints inside their range, geoms named by the URDF link that owns them.

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <map>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_checks.hpp"
#include "retarget/model/robot_guess.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_fit.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// Box [lo, hi] appended to a surface, turned by R.
void add_box(FootSurface& s, const Vec3& lo, const Vec3& hi, const Mat3& R = Mat3::Identity()) {
  const int base = static_cast<int>(s.vertices_F.size());
  for (int k = 0; k < 8; ++k)
    s.vertices_F.push_back(R * Vec3(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z()));
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    s.triangles.push_back({base + f[0], base + f[1], base + f[2]});
    s.triangles.push_back({base + f[0], base + f[2], base + f[3]});
  }
}

TEST(SoleFit, LowestFaceNotTheBoundingBox) {
  // A sole block under a wider upper block: the sole is the bottom face, not the bounds.
  FootSurface s;
  add_box(s, Vec3(-0.05, -0.04, -0.08), Vec3(0.15, 0.04, -0.05));
  add_box(s, Vec3(-0.07, -0.05, -0.05), Vec3(0.17, 0.05, 0.0));
  const SoleFit fit = fit_sole(s);
  EXPECT_TRUE(fit.size_m.isApprox(Vec2(0.20, 0.08), 1e-12)) << fit.size_m.transpose();
  EXPECT_TRUE(fit.p_F_center.isApprox(Vec3(0.05, 0, -0.08), 1e-12)) << fit.p_F_center.transpose();
  EXPECT_TRUE(fit.R_F_S.isApprox(Mat3::Identity(), 1e-12));
  EXPECT_NEAR(fit.tilt_rad, 0, 1e-12);
  EXPECT_EQ(fit.face_vertices, 4);
}

TEST(SoleFit, TiltedSoleGivesItsNormalAndTilt) {
  // The same foot pitched 10 deg (toes down): the face is found with its own normal.
  const Mat3 R = AngleAxis(10 * M_PI / 180, Vec3::UnitY()).toRotationMatrix();
  FootSurface s;
  add_box(s, Vec3(-0.05, -0.04, -0.08), Vec3(0.15, 0.04, -0.05), R);
  const SoleFit fit = fit_sole(s);
  EXPECT_NEAR(fit.tilt_rad, 10 * M_PI / 180, 1e-9);
  EXPECT_TRUE(fit.R_F_S.col(2).isApprox(R.col(2), 1e-9));
  EXPECT_TRUE(fit.size_m.isApprox(Vec2(0.20, 0.08), 1e-9)) << fit.size_m.transpose();
  EXPECT_TRUE(fit.R_F_S.col(0).isApprox(R.col(0), 1e-9));  // forward, in the sole plane
}

TEST(SoleFit, DegenerateBottomHasNoArea) {
  // A foot that ends in a sphere-like point: a tiny "face".
  FootSurface s;
  s.vertices_F = {Vec3(0, 0, -0.1), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), Vec3(-0.1, -0.1, 0)};
  s.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  EXPECT_LT(fit_sole(s).size_m.minCoeff(), 1e-3);
}

std::string odd_yaml() { return test::source_path("tests/data/urdf/odd_biped/robot.yaml"); }

TEST(OddBiped, DerivedSolesFromYUpMeshOnZDownFeet) {
  // package:/// mesh URIs resolve (else the load throws "file not found: /odd_biped/...").
  const auto r = RobotModel::load(odd_yaml());
  RobotData data(*r);
  update_kinematics(*r, data, r->standing_q());
  for (int side = 0; side < 2; ++side) {
    SCOPED_TRACE(side);
    const Sole& sole = r->soles()[static_cast<std::size_t>(side)];
    // The bottom face of the sole block (20 x 8 cm), not the upper block's 24 x 10 cm bounds and
    // not the top of the foot (the link's z points down: the face is at link z = +5 cm).
    EXPECT_TRUE(sole.size_m.isApprox(Vec2(0.20, 0.08), 1e-6)) << sole.size_m.transpose();
    EXPECT_TRUE(sole.p_L_center.isApprox(Vec3(0.05, 0, 0.05), 1e-6)) << sole.p_L_center.transpose();
    const Iso3 X = link_pose(*r, data, sole.link);
    EXPECT_TRUE((X.linear() * sole.R_L_S).isApprox(Mat3::Identity(), 1e-9));  // level, facing +X
    for (const Vec3& c : sole.corners_L()) EXPECT_NEAR((X * c).z(), 0.0, 1e-9);  // on the floor
    // The simulated sole box lies on the sole, above the floor.
    const mjModel* m = r->mj();
    EXPECT_NEAR(data.mj()->geom_xpos[3 * sole.geom + 2], 0.005, 1e-9);
    EXPECT_NEAR(m->geom_size[3 * sole.geom], 0.10, 1e-7);  // MJCF text precision
    EXPECT_NEAR(m->geom_size[3 * sole.geom + 1], 0.04, 1e-7);
  }
  // The sole frames the passes use are the derived ones.
  const auto R_L_sole = sole_frames_in_links(*r, data);
  EXPECT_TRUE(R_L_sole[0].isApprox(r->soles()[0].R_L_S));
}

TEST(OddBiped, UnlistedStandingJointOutsideItsRangeStandsInside) {
  // The knees are left out; their range [0, 2.2] holds 0: they stand at 0. A knee range that
  // excludes 0 is moved just inside the nearer limit, with a note naming the joint.
  const std::string dir = test::scratch_dir();
  std::string urdf = read_file(test::source_path("tests/data/urdf/odd_biped/odd_biped.urdf"), 1 << 20);
  const std::string from = "<limit lower=\"0\" upper=\"2.2\"";
  for (std::size_t at = urdf.find(from); at != std::string::npos; at = urdf.find(from, at))
    urdf.replace(at, from.size(), "<limit lower=\"0.3\" upper=\"2.2\"");
  write_file_atomic(dir + "/odd_biped.urdf", urdf);
  const std::string yaml = "name: odd\nurdf: odd_biped.urdf\npackage_paths: [" + test::source_path("tests/data/urdf") +
                           "]\nfeet:\n  left: {link: left_foot, sole: derive}\n  right: {link: right_foot, sole: derive}\n"
                           "standing_pose:\n  joints: {left_hip: -0.2, right_hip: -0.2}\n";
  const auto r = RobotModel::load(parse_robot_config(yaml, dir + "/robot.yaml"));
  const int knee = r->joints()[static_cast<std::size_t>(r->find_joint("left_knee"))].qpos_index;
  EXPECT_NEAR(r->standing_q()[knee], 0.35, 1e-12);  // 0.3 + min(0.05, 10 % of the range)
  bool noted = false;
  for (const Diagnostic& d : r->diagnostics().items())
    noted |= d.to_string().find("joint 'left_knee' is not listed and 0 is outside its range") != std::string::npos;
  EXPECT_TRUE(noted);
  // An explicit value outside the range is still an error with its line.
  std::string explicit_zero = yaml;
  explicit_zero.replace(explicit_zero.find("right_hip: -0.2}"), 16, "right_hip: -0.2, left_knee: 0}");
  EXPECT_THROW(RobotModel::load(parse_robot_config(explicit_zero, dir + "/robot.yaml")), InputError);
  // The feet stand tilted (hips -0.2, knees 0.35, ankles 0): the derived soles are still the whole
  // bottom face, with its normal.
  EXPECT_TRUE(r->soles()[0].size_m.isApprox(Vec2(0.20, 0.08), 1e-6)) << r->soles()[0].size_m.transpose();
}

TEST(OddBiped, CollisionSpheresAreContactPointsTheSoleComesFromTheVisualMesh) {
  // Feet whose collision geometry is two small spheres (as G1's four 5 mm contact spheres): the
  // derived sole is the visual mesh's bottom face, not the rectangle between the spheres.
  std::string urdf = read_file(test::source_path("tests/data/urdf/odd_biped/odd_biped.urdf"), 1 << 20);
  const std::string from = "<collision>\n      <geometry><mesh filename=\"package:///odd_biped/meshes/foot_y_up.dae\"/></geometry>\n    </collision>";
  const std::string to = "<collision><origin xyz=\"0 0 0.045\"/><geometry><sphere radius=\"0.005\"/></geometry></collision>\n"
                         "    <collision><origin xyz=\"0.1 0 0.045\"/><geometry><sphere radius=\"0.005\"/></geometry></collision>";
  int replaced = 0;
  for (std::size_t at = urdf.find(from); at != std::string::npos; at = urdf.find(from, at + to.size()), ++replaced)
    urdf.replace(at, from.size(), to);
  ASSERT_EQ(replaced, 2);
  const std::string dir = test::scratch_dir();
  write_file_atomic(dir + "/odd_biped.urdf", urdf);
  std::string yaml = read_file(odd_yaml(), 1 << 20);
  yaml.replace(yaml.find("package_paths: [..]"), 19, "package_paths: [" + test::source_path("tests/data/urdf") + "]");
  const auto r = RobotModel::load(parse_robot_config(yaml, dir + "/robot.yaml"));
  EXPECT_TRUE(r->soles()[0].size_m.isApprox(Vec2(0.20, 0.08), 1e-6)) << r->soles()[0].size_m.transpose();
}

TEST(OddBiped, GeomsAreNamedByTheLinkThatOwnsThem) {
  const auto r = RobotModel::load(odd_yaml());
  const mjModel* m = r->mj();
  // The head is merged into the base body, but its sphere belongs to link 'head'.
  const int g = mj_name2id(m, mjOBJ_GEOM, "col_head_0");
  ASSERT_GE(g, 0);
  EXPECT_EQ(r->links()[static_cast<std::size_t>(r->geom_link(g))].name, "head");
  EXPECT_EQ(r->links()[static_cast<std::size_t>(r->body_link(m->geom_bodyid[g]))].name, "base");
  // The soles belong to the foot links (merged into the ankle bodies).
  EXPECT_EQ(r->links()[static_cast<std::size_t>(r->geom_link(r->soles()[0].geom))].name, "left_foot");
  EXPECT_EQ(r->geom_link(r->floor_geom()), -1);
}

// robot.yaml text for odd_biped with `extra` appended, parsed as if in its folder.
RobotConfig odd_config(const std::string& extra) {
  std::string yaml = read_file(odd_yaml(), 1 << 20);
  yaml.erase(yaml.find("base_orientation:"), yaml.find('\n', yaml.find("base_orientation:")) + 1 - yaml.find("base_orientation:"));
  return parse_robot_config(yaml + extra, odd_yaml());
}

TEST(BaseOrientation, AxesOrRpy) {
  const Mat3 Rz_pi = AngleAxis(M_PI, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_TRUE(odd_config("").R_root_F.isApprox(Mat3::Identity()));
  EXPECT_TRUE(odd_config("base_orientation: {forward: -x, up: z}\n").R_root_F.isApprox(Rz_pi, 1e-12));
  EXPECT_TRUE(odd_config("base_orientation: {rpy: [0, 0, 3.141592653589793]}\n").R_root_F.isApprox(Rz_pi, 1e-12));
  // A DH-style root: +y forward, +x up (left = up x forward = +z).
  const Mat3 R = odd_config("base_orientation: {forward: y, up: x}\n").R_root_F;
  EXPECT_TRUE(R.col(0).isApprox(Vec3::UnitY()) && R.col(1).isApprox(Vec3::UnitZ()) && R.col(2).isApprox(Vec3::UnitX()));
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  for (const char* bad : {"base_orientation: {forward: w}\n", "base_orientation: {forward: x, up: -x}\n",
                          "base_orientation: {rpy: [0, 0, 1], up: z}\n", "base_orientation: {yaw: 1}\n"})
    EXPECT_THROW(odd_config(bad), InputError) << bad;
}

TEST(BaseOrientation, BackwardRootStandsFacingForwardAndTheReferenceKeepsTheUrdfRoot) {
  const auto r = RobotModel::load(odd_yaml());
  RobotData data(*r);
  update_kinematics(*r, data, r->standing_q());
  // The pipeline's root body stands upright facing +X; the URDF root link is turned by pi.
  EXPECT_TRUE(r->standing_q().segment<4>(3).isApprox(Vec4(1, 0, 0, 0)));
  const Mat3 Rz_pi = AngleAxis(M_PI, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_TRUE(link_pose(*r, data, r->root_link()).linear().isApprox(Rz_pi, 1e-12));
  // Left is left: the left foot is at +y, the toes at +x.
  const Vec3 left = link_pose(*r, data, r->soles()[kLeftFoot].link).translation();
  const Vec3 right = link_pose(*r, data, r->soles()[kRightFoot].link).translation();
  EXPECT_NEAR(left.y(), 0.1, 1e-9);
  EXPECT_NEAR(right.y(), -0.1, 1e-9);
  const int toe = r->find_link("left_foot");
  EXPECT_GT(link_point(*r, data, toe, Vec3(0.15, 0, 0.05)).x(), left.x() + 0.1);

  // A reference of the standing pose carries the URDF root link's orientation (as a CSV must),
  // and maps back to the same configuration.
  const Reference ref = constant_reference(*r, r->standing_q(), 0.1, 10);
  EXPECT_TRUE(ref.root_quat_W[0].toRotationMatrix().isApprox(Rz_pi, 1e-12));
  const ReferenceRobotMap map(*r, ref, "test");
  const VecX q = map.q(ref, 0);
  EXPECT_TRUE(q.head<3>().isApprox(r->standing_q().head<3>(), 1e-12));
  EXPECT_TRUE(q.tail(r->nu()).isApprox(r->standing_q().tail(r->nu()), 1e-12));
  EXPECT_NEAR(std::abs(q[3]), 1.0, 1e-12);  // the identity (either sign)

  // Without the key the same URDF faces -X, its left foot at -y.
  const auto plain = RobotModel::load(odd_config(""));
  RobotData plain_data(*plain);
  update_kinematics(*plain, plain_data, plain->standing_q());
  EXPECT_NEAR(link_pose(*plain, plain_data, plain->soles()[kLeftFoot].link).translation().y(), -0.1, 1e-9);
}

TEST(JointLimits, OverridesReplaceUrdfValues) {
  const auto r = RobotModel::load(odd_config("joint_limits:\n  left_knee: {velocity: 7.5}\n  right_knee: {effort: 120}\n"));
  const auto movable_index = [&](const char* name) {
    const int j = r->find_joint(name);
    return r->joints()[static_cast<std::size_t>(j)].qpos_index - 7;
  };
  EXPECT_DOUBLE_EQ(r->velocity_limits()[movable_index("left_knee")], 7.5);
  EXPECT_DOUBLE_EQ(r->effort_limits()[movable_index("left_knee")], 80);   // URDF value kept
  EXPECT_DOUBLE_EQ(r->velocity_limits()[movable_index("right_knee")], 10);
  EXPECT_DOUBLE_EQ(r->effort_limits()[movable_index("right_knee")], 120);
  // The simulated motor is clamped at the new effort.
  const int act = movable_index("right_knee");
  EXPECT_DOUBLE_EQ(r->mj()->actuator_forcerange[2 * act + 1], 120);
  EXPECT_THROW(RobotModel::load(odd_config("joint_limits:\n  nope: {velocity: 1}\n")), InputError);
  EXPECT_THROW(odd_config("joint_limits:\n  left_knee: {velocity: 0}\n"), InputError);
  EXPECT_THROW(odd_config("joint_limits:\n  left_knee: {speed: 3}\n"), InputError);
}

bool has_warning(const Diagnostics& d, const std::string& text) {
  for (const Diagnostic& x : d.items())
    if (x.severity == Diagnostic::Severity::Warning && x.to_string().find(text) != std::string::npos) return true;
  return false;
}

TEST(RobotChecks, BackwardRootWithoutBaseOrientationIsFlagged) {
  // Without base_orientation odd_biped faces -X: toes behind the ankles, left foot on the right.
  const auto plain = RobotModel::load(odd_config(""));
  const Diagnostics d = check_robot(*plain);
  EXPECT_TRUE(has_warning(d, "the robot seems to face -X")) << d.items().size();
  EXPECT_TRUE(has_warning(d, "is not to the left of the right foot"));
  // With it: no warning at all.
  const Diagnostics ok = check_robot(*RobotModel::load(odd_yaml()));
  EXPECT_EQ(ok.warning_count(), 0u) << (ok.empty() ? "" : ok.items()[0].to_string());
}

TEST(RobotChecks, TiltedFeetPlaceholderLimitsAndBadInertia) {
  std::string urdf = read_file(test::source_path("tests/data/urdf/odd_biped/odd_biped.urdf"), 1 << 20);
  auto replace_all = [&](const std::string& from, const std::string& to) {
    for (std::size_t at = urdf.find(from); at != std::string::npos; at = urdf.find(from, at + to.size())) urdf.replace(at, from.size(), to);
  };
  replace_all("effort=\"80\" velocity=\"10\"", "effort=\"0\" velocity=\"100\"");   // hips and knees
  replace_all("ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.08\"", "ixx=\"100\" ixy=\"0\" ixz=\"0\" iyy=\"80\"");  // base
  const std::string dir = test::scratch_dir();
  write_file_atomic(dir + "/odd_biped.urdf", urdf);
  std::string yaml = read_file(odd_yaml(), 1 << 20);
  yaml.replace(yaml.find("urdf: odd_biped.urdf"), 20, "urdf: " + dir + "/odd_biped.urdf");
  yaml.replace(yaml.find("package_paths: [..]"), 19, "package_paths: [" + test::source_path("tests/data/urdf") + "]");
  yaml.replace(yaml.find("left_ankle: -0.2"), 16, "left_ankle: 0.25");  // toes up 26 deg
  const auto r = RobotModel::load(parse_robot_config(yaml, dir + "/robot.yaml"));
  const Diagnostics d = check_robot(*r);
  EXPECT_TRUE(has_warning(d, "left sole: its normal is")) << d.items().size();
  EXPECT_FALSE(has_warning(d, "right sole: its normal is"));
  EXPECT_TRUE(has_warning(d, "4 joint(s) have velocity limits >= 50 rad/s"));
  EXPECT_TRUE(has_warning(d, "4 joint(s) have no effort limit"));
  EXPECT_TRUE(has_warning(d, "link 'base': inertia implausible"));
}

TEST(WriteMjcf, TheExportedModelLoadsInMuJoCo) {
  RobotLoadOptions options;
  options.keep_mjcf_assets = true;
  const auto r = RobotModel::load(load_robot_config(odd_yaml()), options);
  const std::string path = test::scratch_dir() + "/odd.xml";
  r->write_mjcf(path);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(m->nbody, r->mj()->nbody);
  EXPECT_EQ(m->ngeom, r->mj()->ngeom);
  EXPECT_EQ(m->nmesh, r->mj()->nmesh);
  EXPECT_NEAR(mj_getTotalmass(m), mj_getTotalmass(r->mj()), 1e-9);
  mj_deleteModel(m);
}

TEST(WriteMjcf, G1WithItsMeshes) {
  RT_REQUIRE_SHARED(urdf, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");
  RobotLoadOptions options;
  options.keep_mjcf_assets = true;
  const auto r = RobotModel::load(load_robot_config("g1"), options);
  ASSERT_GT(r->mj()->nmesh, 0);
  const std::string path = test::scratch_dir() + "/g1.xml";
  r->write_mjcf(path);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(m->nmesh, r->mj()->nmesh);
  EXPECT_EQ(m->ngeom, r->mj()->ngeom);
  EXPECT_EQ(m->nu, r->mj()->nu);
  mj_deleteModel(m);
  // Loaded without its meshes, the model cannot be exported.
  EXPECT_THROW(RobotModel::load(load_robot_config("g1"))->write_mjcf(path), InputError);
}

TEST(InitRobot, BackwardRootZDownFeetAndTripleSlashUrisNeedNoEdit) {
  // odd_biped's URDF alone: the guess finds the legs, that the root faces -X, the feet's soles,
  // and a knees-bent standing pose; the written file loads and passes the checks.
  InitRobotOptions o;
  o.urdf_path = test::source_path("tests/data/urdf/odd_biped/odd_biped.urdf");
  o.package_paths = {test::source_path("tests/data/urdf")};
  const InitRobotResult g = guess_robot_config(o);
  EXPECT_NE(g.yaml.find("base_orientation: {forward: -x, up: z}"), std::string::npos) << g.yaml;
  EXPECT_NE(g.yaml.find("left:  {link: left_foot, sole: derive}"), std::string::npos) << g.yaml;
  EXPECT_NE(g.yaml.find("right: {link: right_foot, sole: derive}"), std::string::npos) << g.yaml;
  const std::string path = test::scratch_dir() + "/robot.yaml";
  write_file_atomic(path, g.yaml);
  const auto r = RobotModel::load(path);
  EXPECT_TRUE(r->config().R_root_F.isApprox(AngleAxis(M_PI, Vec3::UnitZ()).toRotationMatrix(), 1e-12));
  const Diagnostics d = check_robot(*r);
  EXPECT_EQ(d.warning_count(), 0u) << (d.empty() ? "" : d.items()[0].to_string());
  // Knees bent by the default 0.35 rad, feet flat (the soles level at the standing pose).
  const int knee = r->joints()[static_cast<std::size_t>(r->find_joint("left_knee"))].qpos_index;
  EXPECT_NEAR(r->standing_q()[knee], 0.35, 1e-9);
  EXPECT_TRUE(r->soles()[0].size_m.isApprox(Vec2(0.20, 0.08), 1e-6));
  // Landmarks found from the tree: pelvis on the base, knees on the shanks, toes on the feet.
  std::map<std::string, std::string> link_of;
  for (const LandmarkTarget& t : r->config().landmarks) link_of[std::string(landmark_name(t.landmark))] = t.link;
  EXPECT_EQ(link_of["pelvis"], "base");
  EXPECT_EQ(link_of["left_knee"], "left_shank");
  EXPECT_EQ(link_of["right_toe"], "right_foot");
  EXPECT_EQ(link_of.count("left_elbow"), 0u);  // no arms
}

TEST(InitRobot, StandingPoseFromTheSrdfHalfSitting) {
  InitRobotOptions o;
  o.urdf_path = test::source_path("tests/data/urdf/odd_biped/odd_biped.urdf");
  o.package_paths = {test::source_path("tests/data/urdf")};
  o.srdf_path = test::scratch_dir() + "/odd.srdf";
  write_file_atomic(o.srdf_path, R"(<?xml version="1.0"?>
<robot name="odd_biped">
  <group_state name="zero" group="all"><joint name="left_knee" value="0"/></group_state>
  <group_state name="half_sitting" group="all">
    <joint name="left_hip" value="-0.3"/><joint name="left_knee" value="0.6"/><joint name="left_ankle" value="-0.3"/>
    <joint name="right_hip" value="-0.3"/><joint name="right_knee" value="0.6"/><joint name="right_ankle" value="-0.3"/>
    <joint name="no_such_joint" value="1"/>
  </group_state>
</robot>
)");
  const InitRobotResult g = guess_robot_config(o);
  EXPECT_NE(g.yaml.find("SRDF group state 'half_sitting'"), std::string::npos) << g.yaml;
  EXPECT_NE(g.yaml.find("    left_knee: 0.6\n"), std::string::npos) << g.yaml;
  EXPECT_EQ(g.yaml.find("no_such_joint"), std::string::npos);
  // A joint value that is not a number is an error at its line.
  write_file_atomic(o.srdf_path, "<robot name=\"x\">\n<group_state name=\"home\">\n<joint name=\"a\" value=\"abc\"/>\n</group_state>\n</robot>\n");
  try {
    guess_robot_config(o);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), o.srdf_path + ":3");
  }
}

TEST(InitRobot, NoLegsIsAnInputError) {
  InitRobotOptions o;
  o.urdf_path = test::scratch_dir() + "/stick.urdf";
  write_file_atomic(o.urdf_path, R"(<?xml version="1.0"?>
<robot name="stick"><link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<link name="b"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 -0.5"/><axis xyz="0 1 0"/>
<limit lower="-1" upper="1" effort="10" velocity="5"/></joint></robot>
)");
  try {
    guess_robot_config(o);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot find two legs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rt
