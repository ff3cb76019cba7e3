// NPZ layouts (npz_layout.hpp): the MJCF tree reader, the urdf / mjcf: / names: layouts against a
// robot, the joint and body order of the written NPZ, and the mjlab G1 layout against mjlab's own
// MJCF (names, order, body positions = our FK to 1e-9, and = MuJoCo's FK of that MJCF).

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cstring>
#include <fstream>
#include <random>
#include <regex>

#include "formats/mjcf/mjcf_tree.hpp"
#include "formats/reference/reference_npz.hpp"
#include "reference_test_util.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/npz_layout.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

std::string write_text(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

const RobotModel& humanoid25() {
  static const std::unique_ptr<RobotModel> m = RobotModel::load(test::source_path("robots/humanoid25"));
  return *m;
}

std::vector<std::string> names_of(const RobotModel& model, const std::vector<int>& links) {
  std::vector<std::string> out;
  for (int l : links) out.push_back(model.links()[static_cast<std::size_t>(l)].name);
  return out;
}

// A reference of `model` with smooth random joint motion within the limits and a moving root.
Reference moving_reference(const RobotModel& model, int T) {
  Reference r = constant_reference(model, model.standing_q(), (T - 1) / 30.0, 30.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (Eigen::Index j = 0; j < r.joint_pos.rows(); ++j) {
    const int movable = model.export_joint_order()[static_cast<std::size_t>(j)];
    const double lo = model.q_lower()[movable], hi = model.q_upper()[movable];
    const double phase = 6.28 * u(rng), mid = lo + (hi - lo) * (0.3 + 0.4 * u(rng));
    for (int t = 0; t < T; ++t) r.joint_pos(j, t) = mid + 0.25 * (hi - lo) * std::sin(phase + 0.2 * t);
  }
  for (int t = 0; t < T; ++t) {
    r.root_pos_W.col(t) += Vec3(0.02 * t, 0.01 * std::sin(0.3 * t), 0.0);
    r.root_quat_W[static_cast<std::size_t>(t)] = Quat(AngleAxis(0.05 * t, Vec3(0.1, 0.2, 1.0).normalized()));
  }
  return r;
}

TEST(MjcfTree, DocumentOrderThroughFramesWithJoints) {
  const MjcfTree t = parse_mjcf_tree(R"(<mujoco><worldbody>
  <geom name="floor" type="plane" size="1 1 1"/>
  <body name="base"><freejoint/>
    <body name="a"><joint name="ja"/><joint name="ja2" type="slide"/>
      <frame pos="0 0 1"><body name="a1"><joint name="ja1"/></body></frame>
    </body>
    <body name="b"><frame><joint name="jb"/></frame></body>
  </body></worldbody></mujoco>)",
                                     "toy.xml");
  ASSERT_EQ(t.bodies.size(), 4u);
  EXPECT_EQ(t.bodies[0].name, "base");
  EXPECT_EQ(t.bodies[1].name, "a");
  EXPECT_EQ(t.bodies[2].name, "a1");
  EXPECT_EQ(t.bodies[3].name, "b");
  EXPECT_EQ(t.bodies[2].parent, 1);
  EXPECT_EQ(t.bodies[3].parent, 0);
  EXPECT_EQ(t.bodies[0].joints.at(0).type, "free");
  std::vector<std::string> joints;
  for (const MjcfJoint* j : t.movable_joints()) joints.push_back(j->name);
  EXPECT_EQ(joints, (std::vector<std::string>{"ja", "ja2", "ja1", "jb"}));
  EXPECT_EQ(t.bodies[1].line, 4);
}

TEST(MjcfTree, BadFilesAreLocatedOneLineErrors) {
  const auto parse = [](const std::string& text) { return [text] { parse_mjcf_tree(text, "bad.xml"); }; };
  test::expect_input_error(parse("<mujoco><worldbody>\n<body name='a'>\n</mujoco>"), {"bad.xml:", "malformed XML"});
  test::expect_input_error(parse("<robot/>"), {"bad.xml:1", "not an MJCF"});
  test::expect_input_error(parse("<mujoco>\n<asset/></mujoco>"), {"bad.xml:1", "no <worldbody>"});
  test::expect_input_error(parse("<mujoco><worldbody>\n</worldbody></mujoco>"), {"bad.xml:1", "no <body>"});
  test::expect_input_error(parse("<mujoco><worldbody>\n<body pos='0 0 1'/></worldbody></mujoco>"),
                           {"bad.xml:2", "unnamed <body>"});
  test::expect_input_error(parse("<mujoco><worldbody><body name='a'>\n<joint/></body></worldbody></mujoco>"),
                           {"bad.xml:2", "unnamed <joint>"});
  test::expect_input_error(parse("<mujoco><worldbody><body name='a'/>\n<body name='a'/></worldbody></mujoco>"),
                           {"bad.xml:2", "duplicate body name 'a'"});
  test::expect_input_error(parse("<mujoco><worldbody><body name='a'>\n<joint name='j' type='ball'/></body></worldbody></mujoco>"),
                           {"bad.xml:2", "type 'ball'"});
  test::expect_input_error(parse("<mujoco><worldbody>\n<include file='robot.xml'/></worldbody></mujoco>"),
                           {"bad.xml:2", "<include>"});
  test::expect_input_error(parse("<mujoco><worldbody>\n <body name='\xE9'/></worldbody></mujoco>"),
                           {"bad.xml:2:14", "byte 0xE9 is not UTF-8"});
}

TEST(NpzLayout, UrdfLayoutIsRootThenEveryLinkAndExportOrder) {
  const RobotModel& m = humanoid25();
  const NpzLayout l = resolve_npz_layout(m, "urdf", "--npz-layout");
  ASSERT_EQ(l.body_links.size(), m.links().size());
  EXPECT_EQ(l.body_links.front(), m.root_link());
  ASSERT_EQ(static_cast<int>(l.joint_order.size()), m.nu());
  for (std::size_t k = 0; k < l.joint_order.size(); ++k)
    EXPECT_EQ(l.joint_order[k], m.joints()[static_cast<std::size_t>(m.movable_joints()[static_cast<std::size_t>(
                                              m.export_joint_order()[k])])].name);
  test::expect_input_error([&] { resolve_npz_layout(m, "isaac", "--npz-layout"); }, {"--npz-layout", "urdf, mjcf:FILE or names:FILE"});
  test::expect_input_error([&] { resolve_npz_layout(m, "mjcf:/nonexistent/robot.xml", "--npz-layout"); }, {"robot.xml"});
}

TEST(NpzLayout, NamesLayoutOrdersBodiesAndJointsAndLocatesBadNames) {
  const RobotModel& m = humanoid25();
  const std::string dir = test::scratch_dir();
  const NpzLayout urdf = resolve_npz_layout(m, "urdf", "");
  std::vector<std::string> joints = urdf.joint_order;
  std::reverse(joints.begin(), joints.end());
  const std::vector<std::string> all_links = names_of(m, urdf.body_links);
  const std::string bodies = "[" + all_links[3] + ", " + all_links[0] + "]";
  const std::string good = write_text(dir, "good.yaml", "bodies: " + bodies + "\njoints: [" + join(joints, ", ") + "]\n");
  const NpzLayout l = resolve_npz_layout(m, "names:" + good, "--npz-layout");
  EXPECT_EQ(names_of(m, l.body_links), (std::vector<std::string>{all_links[3], all_links[0]}));
  EXPECT_EQ(l.joint_order, joints);
  EXPECT_EQ(read_joint_order(m, good), joints);
  // Bodies only: joints in export order.
  const std::string bodies_only = write_text(dir, "bodies.yaml", "bodies: " + bodies + "\n");
  EXPECT_EQ(resolve_npz_layout(m, "names:" + bodies_only, "").joint_order, urdf.joint_order);
  // A plain list for --joint-order.
  const std::string list = write_text(dir, "list.yaml", "[" + join(joints, ", ") + "]\n");
  EXPECT_EQ(read_joint_order(m, list), joints);

  const auto bad = [&](const std::string& text) {
    const std::string p = write_text(dir, "bad.yaml", text);
    return [&m, p] { resolve_npz_layout(m, "names:" + p, "--npz-layout"); };
  };
  test::expect_input_error(bad("bodies: [" + all_links[0] + ",\n  no_such_link]\n"), {"bad.yaml:2", "bodies[1]", "no_such_link"});
  test::expect_input_error(bad("bodies: [" + all_links[0] + ", " + all_links[0] + "]\n"), {"bad.yaml:1", "listed twice"});
  test::expect_input_error(bad("bodies: []\n"), {"bad.yaml:1", "at least one body"});
  test::expect_input_error(bad("joints: [" + joints[0] + "]\n"), {"bad.yaml:1", "joints", "is missing", "1 of 25"});
  test::expect_input_error(bad("joints: [" + joints[0] + ", nope]\n"), {"bad.yaml:1", "joints[1]", "'nope' is not a movable joint"});
  test::expect_input_error(bad("bodys: [a]\n"), {"bad.yaml:1", "bodys"});
}

TEST(NpzLayout, MjcfLayoutChecksBodiesAndJointsAgainstTheUrdf) {
  // A toy MJCF for humanoid25: its links in another order than the URDF's, as a simulator may
  // number them, and wrong trees that must be refused.
  const RobotModel& m = humanoid25();
  const std::string dir = test::scratch_dir();
  const NpzLayout urdf = resolve_npz_layout(m, "urdf", "");
  const std::string root = m.links()[static_cast<std::size_t>(m.root_link())].name;
  // Child links of the root with their joints, last child first.
  std::vector<std::pair<std::string, std::string>> kids;
  for (int j : m.links()[static_cast<std::size_t>(m.root_link())].child_joints) {
    const Joint& joint = m.joints()[static_cast<std::size_t>(j)];
    if (joint.qpos_index >= 0) kids.emplace_back(m.links()[static_cast<std::size_t>(joint.child_link)].name, joint.name);
  }
  ASSERT_GE(kids.size(), 2u);
  std::reverse(kids.begin(), kids.end());
  std::string xml = "<mujoco><worldbody>\n<body name='" + root + "'><freejoint/>\n";
  for (const auto& [link, joint] : kids) xml += "<body name='" + link + "'><joint name='" + joint + "'/></body>\n";
  xml += "</body></worldbody></mujoco>\n";
  const std::string partial = write_text(dir, "partial.xml", xml);
  // Not every movable joint is in it.
  test::expect_input_error([&] { resolve_npz_layout(m, "mjcf:" + partial, ""); }, {"partial.xml", "is missing"});

  const auto bad = [&](const std::string& text) {
    const std::string p = write_text(dir, "bad.xml", text);
    return [&m, p] { resolve_npz_layout(m, "mjcf:" + p, ""); };
  };
  test::expect_input_error(bad("<mujoco><worldbody>\n<body name='" + root + "'>\n<body name='nolink'/></body></worldbody></mujoco>"),
                           {"bad.xml:3", "'nolink' is not a link"});
  test::expect_input_error(bad("<mujoco><worldbody>\n<body name='" + kids[0].first + "'/></worldbody></mujoco>"),
                           {"bad.xml:2", "not the URDF root"});
  // A joint in the body of another link.
  test::expect_input_error(bad("<mujoco><worldbody>\n<body name='" + root + "'><freejoint/>\n<body name='" + kids[0].first +
                               "'>\n<joint name='" + kids[1].second + "'/></body></body></worldbody></mujoco>"),
                           {"bad.xml:4", "'" + kids[1].second + "' is in body '" + kids[0].first + "'"});
  // A body nested under a body that is not its URDF ancestor.
  test::expect_input_error(bad("<mujoco><worldbody>\n<body name='" + root + "'><freejoint/>\n<body name='" + kids[0].first +
                               "'>\n<body name='" + kids[1].first + "'/></body></body></worldbody></mujoco>"),
                           {"bad.xml:4", "not above link"});
  (void)urdf;
}

TEST(NpzLayout, NpzJointColumnsFollowTheLayoutAndReadBack) {
  const RobotModel& m = humanoid25();
  const std::string dir = test::scratch_dir();
  const NpzLayout urdf = resolve_npz_layout(m, "urdf", "");
  std::vector<std::string> joints = urdf.joint_order;
  std::rotate(joints.begin(), joints.begin() + 5, joints.end());
  const std::string root = m.links()[static_cast<std::size_t>(m.root_link())].name;
  const std::string file = write_text(dir, "order.yaml", "bodies: [" + root + "]\njoints: [" + join(joints, ", ") + "]\n");
  const NpzLayout layout = resolve_npz_layout(m, "names:" + file, "");
  const Reference ref = moving_reference(m, 12);
  RobotData data(m);
  const NpzBodyArrays bodies = compute_body_arrays(m, data, ref, layout);
  NpzBodyArrays back_bodies;
  const Reference back = decode_reference_npz(encode_reference_npz(ref, &bodies), "x.npz", {}, &back_bodies);
  EXPECT_EQ(back.joint_names, joints);
  EXPECT_EQ(back_bodies.joint_order, joints);
  EXPECT_EQ(back_bodies.body_names, std::vector<std::string>{root});
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const auto src = std::find(ref.joint_names.begin(), ref.joint_names.end(), joints[k]) - ref.joint_names.begin();
    EXPECT_EQ(back.joint_pos.row(static_cast<Eigen::Index>(k)), ref.joint_pos.row(src)) << joints[k];
  }
}

// mjlab's G1 MJCF without its meshes (not shipped), for MuJoCo's own forward kinematics.
std::string without_meshes(std::string xml) {
  xml = std::regex_replace(xml, std::regex("<mesh [^>]*/>"), "");
  xml = std::regex_replace(xml, std::regex("<geom [^>]*mesh=\"[^\"]*\"[^>]*/>"), "");
  return xml;
}

TEST(NpzLayout, MjlabG1OrderNamesAndBodyPositions) {
  RT_REQUIRE_SHARED(mjcf, "robots/unitree_g1/mjlab/g1.xml");
  const std::unique_ptr<RobotModel> g1 = RobotModel::load(test::source_path("robots/g1"));
  const MjcfTree tree = read_mjcf_tree(mjcf);
  const NpzLayout layout = resolve_npz_layout(*g1, "mjcf:" + mjcf, "--npz-layout");
  // 30 bodies in the MJCF's order (the URDF has 39 links: 9 fixed ones merged), joints in its order.
  ASSERT_EQ(layout.body_links.size(), 30u);
  EXPECT_EQ(g1->links().size(), 39u);
  for (std::size_t b = 0; b < tree.bodies.size(); ++b)
    EXPECT_EQ(g1->links()[static_cast<std::size_t>(layout.body_links[b])].name, tree.bodies[b].name);
  std::vector<std::string> mjcf_joints;
  for (const MjcfJoint* j : tree.movable_joints()) mjcf_joints.push_back(j->name);
  EXPECT_EQ(layout.joint_order, mjcf_joints);
  EXPECT_EQ(names_of(*g1, layout.body_links)[15], "torso_link");  // mjlab's anchor body

  // G1's default layout (robots/g1/mjlab_order.yaml) is exactly this order.
  const NpzLayout shipped = resolve_npz_layout(*g1, g1->config().npz_layout, "robot.yaml");
  EXPECT_EQ(shipped.body_links, layout.body_links);
  EXPECT_EQ(shipped.joint_order, layout.joint_order);
  EXPECT_EQ(read_joint_order(*g1, mjcf), mjcf_joints);

  // Through the NPZ: body positions equal our FK of those links (1e-9), and MuJoCo's FK of the
  // MJCF itself (to the MJCF's printed precision).
  const Reference ref = moving_reference(*g1, 20);
  RobotData data(*g1);
  const NpzBodyArrays bodies = compute_body_arrays(*g1, data, ref, layout);
  NpzBodyArrays nb;
  const Reference npz = decode_reference_npz(encode_reference_npz(ref, &bodies), "g1.npz", {}, &nb);
  ASSERT_EQ(nb.body_names.size(), 30u);
  EXPECT_EQ(npz.joint_names, mjcf_joints);

  char error[1000] = "";
  const std::string stripped = without_meshes(read_file(mjcf));
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  ASSERT_EQ(mj_makeEmptyFileVFS(&vfs, "g1.xml", static_cast<int>(stripped.size())), 0);
  const int file = mj_findFileVFS(&vfs, "g1.xml");
  std::memcpy(vfs.filedata[file], stripped.data(), stripped.size());
  mjModel* mm = mj_loadXML("g1.xml", &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  ASSERT_NE(mm, nullptr) << error;
  mjData* md = mj_makeData(mm);
  const ReferenceRobotMap map(*g1, ref, "ref");
  double worst_fk = 0, worst_mj = 0, worst_mj_quat = 0;
  for (int t = 0; t < ref.num_frames(); ++t) {
    update_kinematics(*g1, data, map.q(ref, t));
    for (std::size_t b = 0; b < 30; ++b)
      worst_fk = std::max(worst_fk, (nb.p_W_body[b].col(t) - link_pose(*g1, data, layout.body_links[b]).translation()).norm());
    // MuJoCo qpos: the free joint (position, w x y z), then the NPZ's joint columns (MJCF order).
    for (int i = 0; i < 3; ++i) md->qpos[i] = npz.root_pos_W(i, t);
    const Quat& q = npz.root_quat_W[static_cast<std::size_t>(t)];
    md->qpos[3] = q.w(), md->qpos[4] = q.x(), md->qpos[5] = q.y(), md->qpos[6] = q.z();
    ASSERT_EQ(mm->nq, 7 + static_cast<int>(npz.joint_names.size()));
    for (Eigen::Index j = 0; j < npz.joint_pos.rows(); ++j) md->qpos[7 + j] = npz.joint_pos(j, t);
    mj_kinematics(mm, md);
    for (std::size_t b = 0; b < 30; ++b) {
      const int id = mj_name2id(mm, mjOBJ_BODY, nb.body_names[b].c_str());
      ASSERT_EQ(id, static_cast<int>(b) + 1) << nb.body_names[b];  // NPZ body b = MuJoCo body b + 1
      const Vec3 p(md->xpos[3 * id], md->xpos[3 * id + 1], md->xpos[3 * id + 2]);
      worst_mj = std::max(worst_mj, (p - nb.p_W_body[b].col(t)).norm());
      const Quat qm(md->xquat[4 * id], md->xquat[4 * id + 1], md->xquat[4 * id + 2], md->xquat[4 * id + 3]);
      worst_mj_quat = std::max(worst_mj_quat, qm.angularDistance(nb.q_W_body[b][static_cast<std::size_t>(t)]));
    }
  }
  mj_deleteData(md);
  mj_deleteModel(mm);
  EXPECT_LE(worst_fk, 1e-9);
  EXPECT_LE(worst_mj, 1e-5) << "MuJoCo's FK of mjlab's MJCF";
  EXPECT_LE(worst_mj_quat, 1e-4);
}

}  // namespace
}  // namespace rt
