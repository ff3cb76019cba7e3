// RobotModel: the generated MuJoCo model (free joint, merged inertias, joints, motors, floor, soles,
// collision filtering, meshes), the standing pose, and model-level rejections.

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <filesystem>
#include <fstream>
#include <thread>

#include "formats/mesh/triangle_mesh.hpp"
#include "formats/urdf/urdf_description.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

std::string mini_yaml() { return test::source_path("tests/data/urdf/mini_biped/robot.yaml"); }

const RobotModel& mini() {
  static const std::unique_ptr<RobotModel> model = RobotModel::load(mini_yaml());
  return *model;
}

// A config for a URDF written to the test's scratch folder, with explicit soles.
RobotConfig inline_config(const std::string& urdf_text, const std::string& left_foot, const std::string& right_foot) {
  RobotConfig c;
  c.name = "inline";
  c.urdf_path = test::scratch_dir() + "/robot.urdf";
  c.config_path = c.urdf_path;
  write_file_atomic(c.urdf_path, urdf_text);
  c.feet[kLeftFoot].link = left_foot;
  c.feet[kRightFoot].link = right_foot;
  for (auto& f : c.feet) {
    f.sole.p_L_center = Vec3(0, 0, -0.02);
    f.sole.size_m = Vec2(0.2, 0.1);
  }
  return c;
}

// Two boxes for feet on a pelvis: the smallest robot RobotModel accepts.
std::string two_feet(const std::string& extra_links = "", const std::string& pelvis_extra = "") {
  return R"(<?xml version="1.0"?>
<robot name="inline">
  <link name="pelvis">
    <inertial><mass value="5"/><inertia ixx="0.05" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.05"/></inertial>
)" + pelvis_extra + R"(
  </link>
  <link name="lfoot">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><box size="0.2 0.1 0.04"/></geometry></collision>
  </link>
  <link name="rfoot">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="lhip" type="revolute"><parent link="pelvis"/><child link="lfoot"/><origin xyz="0 0.1 -0.5"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="50" velocity="5"/></joint>
  <joint name="rhip" type="revolute"><parent link="pelvis"/><child link="rfoot"/><origin xyz="0 -0.1 -0.5"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="50" velocity="5"/></joint>
)" + extra_links + "</robot>\n";
}

Mat3 body_inertia_in_body_axes(const mjModel* m, int b) {
  const Mat3 R = Quat(m->body_iquat[4 * b], m->body_iquat[4 * b + 1], m->body_iquat[4 * b + 2], m->body_iquat[4 * b + 3])
                     .toRotationMatrix();
  return R * Eigen::Map<const Vec3>(m->body_inertia + 3 * b).asDiagonal() * R.transpose();
}

TEST(RobotModel, FreeJointAndSizes) {
  const RobotModel& r = mini();
  const mjModel* m = r.mj();
  EXPECT_EQ(r.nu(), 10);
  EXPECT_EQ(r.nq(), 17);
  EXPECT_EQ(r.nv(), 16);
  EXPECT_EQ(m->nq, r.nq());
  EXPECT_EQ(m->nv, r.nv());
  EXPECT_EQ(m->nu, r.nu());
  EXPECT_EQ(m->jnt_type[0], mjJNT_FREE);
  EXPECT_EQ(m->jnt_bodyid[0], r.root_body());
  EXPECT_EQ(r.links()[static_cast<std::size_t>(r.root_link())].name, "pelvis");
  EXPECT_EQ(r.body_link(r.root_body()), r.root_link());
  EXPECT_EQ(r.body_link(0), -1);
  // The URDF's empty world link above its floating joint is MuJoCo's world body.
  EXPECT_EQ(r.links()[static_cast<std::size_t>(r.find_link("world"))].body, 0);
  EXPECT_EQ(r.joints()[static_cast<std::size_t>(r.find_joint("float_base"))].qpos_index, -1);
}

TEST(RobotModel, MovableJointsInQposOrderWithTheirProperties) {
  const RobotModel& r = mini();
  const mjModel* m = r.mj();
  ASSERT_EQ(r.movable_joints().size(), 10u);
  for (int k = 0; k < r.nu(); ++k) {
    const Joint& j = r.joints()[static_cast<std::size_t>(r.movable_joints()[static_cast<std::size_t>(k)])];
    const int id = mj_name2id(m, mjOBJ_JOINT, j.name.c_str());
    ASSERT_GE(id, 0) << j.name;
    EXPECT_EQ(m->jnt_qposadr[id], 7 + k);
    EXPECT_EQ(m->jnt_dofadr[id], 6 + k);
    EXPECT_EQ(j.qpos_index, 7 + k);
    EXPECT_EQ(j.dof_index, 6 + k);
    EXPECT_EQ(m->jnt_limited[id], j.has_position_limits ? 1 : 0) << j.name;
    if (j.has_position_limits) {
      EXPECT_EQ(m->jnt_range[2 * id], j.lower);
      EXPECT_EQ(m->jnt_range[2 * id + 1], j.upper);
      EXPECT_EQ(r.q_lower()[k], j.lower);
      EXPECT_EQ(r.q_upper()[k], j.upper);
    } else {
      EXPECT_EQ(r.q_lower()[k], -std::numeric_limits<double>::infinity());
    }
    EXPECT_EQ(m->jnt_type[id], j.type == JointType::Prismatic ? mjJNT_SLIDE : mjJNT_HINGE);
    EXPECT_EQ(m->dof_armature[6 + k], j.name == "waist" ? 0.05 : 0.02) << j.name;
    EXPECT_DOUBLE_EQ(m->dof_damping[6 + k], j.damping + 0.1) << j.name;
    EXPECT_EQ(m->dof_frictionloss[6 + k], j.friction);
    // Motor k drives joint k, clamped to the URDF effort.
    EXPECT_EQ(m->actuator_trnid[2 * k], id);
    EXPECT_EQ(m->actuator_gear[6 * k], 1);
    EXPECT_EQ(m->actuator_forcerange[2 * k + 1], j.effort_limit);
    EXPECT_EQ(m->actuator_ctrlrange[2 * k], -j.effort_limit);
    EXPECT_TRUE(m->actuator_forcelimited[k]);
    EXPECT_EQ(r.effort_limits()[k], j.effort_limit);
    EXPECT_EQ(r.velocity_limits()[k], j.velocity_limit);
  }
  const Joint& waist = r.joints()[static_cast<std::size_t>(r.find_joint("waist"))];
  EXPECT_EQ(waist.type, JointType::Continuous);
  EXPECT_DOUBLE_EQ(m->dof_damping[waist.dof_index], 0.6);
  EXPECT_DOUBLE_EQ(m->dof_frictionloss[waist.dof_index], 0.2);
  // Depth-first model order with children in URDF document order.
  std::vector<std::string> names;
  for (int j : r.movable_joints()) names.push_back(r.joints()[static_cast<std::size_t>(j)].name);
  EXPECT_EQ(names, (std::vector<std::string>{"waist", "neck_lift", "left_shoulder", "right_shoulder", "left_hip", "left_knee",
                                             "left_ankle", "right_hip", "right_knee", "right_ankle"}));
  // Default export order: URDF document order of the movable joints.
  std::vector<std::string> exported;
  for (int k : r.export_joint_order()) exported.push_back(names[static_cast<std::size_t>(k)]);
  EXPECT_EQ(exported, (std::vector<std::string>{"waist", "neck_lift", "left_shoulder", "left_hip", "left_knee", "left_ankle",
                                                "right_shoulder", "right_hip", "right_knee", "right_ankle"}));
}

TEST(RobotModel, MergedInertiaIsTheSumOfItsLinks) {
  const RobotModel& r = mini();
  const mjModel* m = r.mj();
  // Total mass: MuJoCo equals the URDF sum.
  UrdfReadOptions options;
  options.package_paths = r.config().package_paths;
  const UrdfRobot urdf = read_urdf_file(r.config().urdf_path, options);
  double urdf_mass = 0;
  for (const auto& l : urdf.links) urdf_mass += l.inertial.mass_kg;
  EXPECT_NEAR(mj_getTotalmass(m), urdf_mass, 1e-9);
  EXPECT_NEAR(r.total_mass_kg(), urdf_mass, 1e-9);

  // The root body holds pelvis + imu (massless) + battery; recompute independently from the URDF.
  const UrdfLink& pelvis = urdf.links[static_cast<std::size_t>(urdf.find_link("pelvis"))];
  const UrdfLink& battery = urdf.links[static_cast<std::size_t>(urdf.find_link("battery"))];
  const Iso3 X_P_B = urdf.joints[static_cast<std::size_t>(urdf.find_joint("battery_joint"))].X_P_J;
  const double mass = pelvis.inertial.mass_kg + battery.inertial.mass_kg;
  const Vec3 c1 = pelvis.inertial.p_L_com, c2 = X_P_B * battery.inertial.p_L_com;
  const Vec3 com = (pelvis.inertial.mass_kg * c1 + battery.inertial.mass_kg * c2) / mass;
  auto shift = [](double mi, const Vec3& d) { return mi * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()); };
  const Mat3 I = pelvis.inertial.I_com + shift(pelvis.inertial.mass_kg, c1 - com) +
                 X_P_B.linear() * battery.inertial.I_com * X_P_B.linear().transpose() + shift(battery.inertial.mass_kg, c2 - com);
  const int b = r.root_body();
  EXPECT_NEAR(m->body_mass[b], mass, 1e-12);
  EXPECT_TRUE(Eigen::Map<const Vec3>(m->body_ipos + 3 * b).isApprox(com, 1e-12));
  EXPECT_TRUE(body_inertia_in_body_axes(m, b).isApprox(I, 1e-12)) << body_inertia_in_body_axes(m, b) << "\n" << I;

  // Merged links record their body and pose in it.
  const Link& battery_link = r.links()[static_cast<std::size_t>(r.find_link("battery"))];
  EXPECT_EQ(battery_link.body, r.root_body());
  EXPECT_TRUE(battery_link.X_B_L.isApprox(X_P_B));

  // Whole-body COM at the standing pose equals the mass-weighted COM of every URDF link placed by
  // link_pose (merged links included).
  RobotData data(r);
  update_kinematics(r, data, r.standing_q());
  Vec3 sum = Vec3::Zero();
  for (std::size_t l = 0; l < r.links().size(); ++l)
    sum += r.links()[l].inertial.mass_kg * (link_pose(r, data, static_cast<int>(l)) * r.links()[l].inertial.p_L_com);
  EXPECT_TRUE(com_position(r, data).isApprox(sum / urdf_mass, 1e-12));
  EXPECT_NEAR(r.standing_com_height_m(), sum.z() / urdf_mass, 1e-12);
}

TEST(RobotModel, SolesGeomsAndCollisionFiltering) {
  const RobotModel& r = mini();
  const mjModel* m = r.mj();
  // Left sole derived from the foot's collision box equals the explicit right one.
  for (int s : {kLeftFoot, kRightFoot}) {
    const Sole& sole = r.soles()[static_cast<std::size_t>(s)];
    EXPECT_TRUE(sole.p_L_center.isApprox(Vec3(0.03, 0, -0.06), 1e-12));
    EXPECT_TRUE(sole.size_m.isApprox(Vec2(0.22, 0.1), 1e-12));
    ASSERT_GE(sole.geom, 0);
    EXPECT_EQ(r.sole_side(sole.geom), s);
    EXPECT_EQ(m->geom_type[sole.geom], mjGEOM_BOX);
    EXPECT_EQ(m->geom_group[sole.geom], RobotModel::kSoleGeomGroup);
    EXPECT_NEAR(m->geom_size[3 * sole.geom], 0.11, 1e-12);
    EXPECT_NEAR(m->geom_size[3 * sole.geom + 1], 0.05, 1e-12);
    EXPECT_EQ(m->geom_bodyid[sole.geom], r.links()[static_cast<std::size_t>(sole.link)].body);
  }
  EXPECT_EQ(r.sole_side(r.floor_geom()), -1);
  EXPECT_EQ(m->geom_type[r.floor_geom()], mjGEOM_PLANE);
  // Foot links' own collision geometry is replaced by the sole; the rest is kept, named col_*.
  EXPECT_EQ(mj_name2id(m, mjOBJ_GEOM, "col_left_foot_0"), -1);
  EXPECT_GE(mj_name2id(m, mjOBJ_GEOM, "col_torso_0"), 0);
  EXPECT_GE(mj_name2id(m, mjOBJ_GEOM, "col_battery_0"), 0);
  EXPECT_EQ(m->ngeom, 13);  // floor + 2 soles + 10 collision geoms
  EXPECT_EQ(m->nmesh, 3);   // torso, arm, mirrored arm
  int robot_geoms = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (g == r.floor_geom()) continue;
    ++robot_geoms;
    const bool sole = r.sole_side(g) >= 0;
    if (!sole) {
      EXPECT_EQ(m->geom_group[g], RobotModel::kCollisionGeomGroup);
      EXPECT_EQ(std::string(mj_id2name(m, mjOBJ_GEOM, g)).rfind("col_", 0), 0u);
    }
    // Every robot geom touches the floor, none touches another robot geom.
    const int f = r.floor_geom();
    EXPECT_TRUE((m->geom_contype[g] & m->geom_conaffinity[f]) || (m->geom_contype[f] & m->geom_conaffinity[g]));
    for (int h = 0; h < m->ngeom; ++h)
      if (h != f) {
        EXPECT_FALSE((m->geom_contype[g] & m->geom_conaffinity[h]) || (m->geom_contype[h] & m->geom_conaffinity[g]));
      }
    // ... and MuJoCo tests exactly the floor pairs, with the geoms' own friction and condim.
    int pairs = 0;
    for (int p = 0; p < m->npair; ++p) {
      if (!((m->pair_geom1[p] == f && m->pair_geom2[p] == g) || (m->pair_geom1[p] == g && m->pair_geom2[p] == f))) continue;
      ++pairs;
      EXPECT_EQ(m->pair_dim[p], m->geom_condim[g]);
      EXPECT_EQ(m->pair_friction[5 * p], m->geom_friction[3 * g]);
      EXPECT_EQ(m->pair_friction[5 * p + 1], m->geom_friction[3 * g]);
    }
    EXPECT_EQ(pairs, 1);
  }
  EXPECT_EQ(robot_geoms, 12);
  EXPECT_EQ(m->npair, robot_geoms);
  EXPECT_EQ(m->opt.collision, mjCOL_PAIR);
}

TEST(RobotModel, StandingPoseTouchesTheFloor) {
  const RobotModel& r = mini();
  const VecX& q = r.standing_q();
  ASSERT_EQ(q.size(), r.nq());
  EXPECT_EQ(q.segment<2>(0), Vec2::Zero());
  EXPECT_EQ(q.segment<4>(3), Vec4(1, 0, 0, 0));
  const Joint& knee = r.joints()[static_cast<std::size_t>(r.find_joint("left_knee"))];
  EXPECT_EQ(q[knee.qpos_index], 0.4);
  const Joint& waist = r.joints()[static_cast<std::size_t>(r.find_joint("waist"))];
  EXPECT_EQ(q[waist.qpos_index], 0.0);
  RobotData data(r);
  update_kinematics(r, data, q);
  double lowest = 1e9;
  for (const Sole& s : r.soles())
    for (const Vec3& c : s.corners_L()) lowest = std::min(lowest, link_point(r, data, s.link, c).z());
  EXPECT_NEAR(lowest, 0.0, 1e-12);
  // mjModel's qpos0 has the root there too.
  EXPECT_NEAR(r.mj()->qpos0[2], q[2], 1e-12);
}

TEST(RobotModel, ConfiguredRootHeightIsUsed) {
  RobotConfig c = load_robot_config(mini_yaml());
  c.standing_root_height_m = 1.25;
  const auto r = RobotModel::load(c);
  EXPECT_EQ(r->standing_q()[2], 1.25);
}

TEST(RobotModel, FixedRootWithoutFloatingJointGetsAFreeJoint) {
  const auto r = RobotModel::load(inline_config(two_feet(), "lfoot", "rfoot"));
  EXPECT_EQ(r->nq(), 9);
  EXPECT_EQ(r->mj()->jnt_type[0], mjJNT_FREE);
  EXPECT_EQ(r->links()[static_cast<std::size_t>(r->root_link())].name, "pelvis");
  EXPECT_NEAR(mj_getTotalmass(r->mj()), 7.0, 1e-12);
  EXPECT_TRUE(r->diagnostics().empty());
}

TEST(RobotModel, MasslessMovingBodyGetsATinyMassAndAWarning) {
  const std::string extra = R"(
  <link name="antenna"/>
  <joint name="antenna_joint" type="revolute"><parent link="pelvis"/><child link="antenna"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
)";
  const auto r = RobotModel::load(inline_config(two_feet(extra), "lfoot", "rfoot"));
  const int body = r->links()[static_cast<std::size_t>(r->find_link("antenna"))].body;
  EXPECT_NEAR(r->mj()->body_mass[body], 1e-3, 1e-15);
  EXPECT_NEAR(r->total_mass_kg(), 7.0, 1e-12);  // the URDF's mass
  ASSERT_GE(r->diagnostics().warning_count(), 1u);
  EXPECT_NE(r->diagnostics().items()[0].message.find("'antenna' moves but has no mass"), std::string::npos);
}

TEST(RobotModel, FlatCollisionMeshBecomesAThinBox) {
  // A flat square: qhull cannot build its hull, so it must not reach MuJoCo as a mesh.
  TriangleMesh plate;
  plate.vertices = {{0, 0, 0}, {0.1, 0, 0}, {0.1, 0.2, 0}, {0, 0.2, 0}};
  plate.faces = {{0, 1, 2}, {0, 2, 3}};
  const RobotConfig c = inline_config(
      two_feet("", "<collision><geometry><mesh filename=\"plate.stl\"/></geometry></collision>"), "lfoot", "rfoot");
  write_file_atomic((std::filesystem::path(c.urdf_path).parent_path() / "plate.stl").string(), to_binary_stl(plate));
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  const auto r = RobotModel::load(c);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  const int g = mj_name2id(r->mj(), mjOBJ_GEOM, "col_pelvis_0");
  ASSERT_GE(g, 0);
  EXPECT_EQ(r->mj()->geom_type[g], mjGEOM_BOX);
  EXPECT_EQ(r->mj()->nmesh, 0);
  EXPECT_NE(r->diagnostics().items().at(0).message.find("is flat"), std::string::npos);
}

TEST(RobotModel, RejectsFloatingJointBelowTheRoot) {
  const std::string extra = R"(
  <link name="drone"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="drone_joint" type="floating"><parent link="pelvis"/><child link="drone"/></joint>
)";
  const RobotConfig c = inline_config(two_feet(extra), "lfoot", "rfoot");
  try {
    RobotModel::load(c);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), c.urdf_path + ":20");
    EXPECT_EQ(e.message(), "floating joint 'drone_joint' is supported only as the single joint below an empty root link (a "
                           "'world' link); the generated model gives the root a free joint anyway");
  }
}

TEST(RobotModel, LinkAndJointLookup) {
  const RobotModel& r = mini();
  EXPECT_EQ(r.find_link("nope"), -1);
  EXPECT_EQ(r.link_index("torso"), r.find_link("torso"));
  EXPECT_THROW(r.link_index("nope"), InputError);
  EXPECT_THROW(r.joint_index("nope"), InputError);
  EXPECT_EQ(r.joint_index("waist"), r.find_joint("waist"));
  EXPECT_EQ(r.name(), "mini_biped");
  EXPECT_NE(r.mjcf().find("<freejoint"), std::string::npos);
}

TEST(RobotModel, ParallelLoadsAreSerialisedAndIdentical) {
  std::vector<std::unique_ptr<RobotModel>> models(4);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < models.size(); ++i) threads.emplace_back([&, i] { models[i] = RobotModel::load(mini_yaml()); });
  for (auto& t : threads) t.join();
  for (const auto& m : models) {
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->mjcf(), mini().mjcf());
    EXPECT_EQ(m->standing_q(), mini().standing_q());
  }
}

TEST(RobotModel, MuJoCoWarningsAreNotPrinted) {
  // Loading installs hooks so that MuJoCo's runtime warnings are counted, never printed.
  (void)mini();
  EXPECT_NE(mju_user_warning, nullptr);
  EXPECT_NE(mju_user_error, nullptr);
}

}  // namespace
}  // namespace rt
