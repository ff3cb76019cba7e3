// The motion viewer's page generation (motion_viewer.hpp): the scene against the robot's own
// forward kinematics, the embedded data round trip, the size bound of a 10 s G1 page, and located
// errors for bad input. The page in a real browser is tested in tests/cli/view_cli_test.cpp.

#include "retarget/report/motion_viewer.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "retarget/core/error.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/reference/synthetic_references.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

const RobotModel& humanoid25() {
  static const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  return *model;
}

// A stand-in for three.js, so that page generation is tested without libjs-three; its "</script>"
// must not end the script element.
ViewerOptions fake_three_options() {
  const std::string dir = test::scratch_dir() + "/three";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/three.min.js") << "var THREE = {REVISION: 'fake', s: '</script>'};\n";
  ViewerOptions o;
  o.three_js_dir = dir;
  return o;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MotionViewer, Base64RoundTripAndErrors) {
  std::mt19937 rng(7);
  for (std::size_t n = 0; n < 40; ++n) {
    std::string bytes(n, '\0');
    for (char& c : bytes) c = static_cast<char>(rng() & 255);
    const std::string text = base64_encode(bytes.data(), bytes.size());
    EXPECT_EQ(text.size() % 4, 0u);
    EXPECT_EQ(base64_decode(text, "x"), bytes) << n;
  }
  EXPECT_EQ(base64_encode("Man", 3), "TWFu");
  EXPECT_EQ(base64_encode("Ma", 2), "TWE=");
  EXPECT_EQ(base64_encode("M", 1), "TQ==");
  EXPECT_EQ(error_of([] { base64_decode("TWF", "page [k]"); }), "page [k]: base64 length 3 is not a multiple of 4");
  EXPECT_EQ(error_of([] { base64_decode("TW*u", "page [k]"); }), "page [k]: character 2 is not base64");
}

TEST(MotionViewer, RobotSceneStandsOnTheFloorWithItsLandmarks) {
  const RobotModel& model = humanoid25();
  const ViewerScene s = robot_scene(model);
  EXPECT_EQ(s.mode, "robot");
  EXPECT_EQ(s.num_frames, 1);
  EXPECT_EQ(s.link_poses.size(), static_cast<std::size_t>(s.num_links()) * 7);
  EXPECT_GT(s.meshes.size(), 10u);  // humanoid25: boxes, cylinders and spheres
  EXPECT_EQ(s.mesh_source, "visual");  // its URDF gives visual primitives
  ASSERT_EQ(s.landmarks.names.size(), model.config().landmarks.size());
  EXPECT_EQ(s.landmarks.p_W.size(), 3 * s.landmarks.names.size());
  EXPECT_EQ(s.contact[0], std::vector<std::uint8_t>{1});
  // The standing pose puts the lowest sole on the floor: every sole corner at z = 0 (float32).
  ASSERT_EQ(s.sole_corners_W.size(), 24u);
  double zmin = 1e9;
  for (std::size_t i = 2; i < 24; i += 3) zmin = std::min(zmin, static_cast<double>(s.sole_corners_W[i]));
  EXPECT_NEAR(zmin, 0.0, 1e-5);
  EXPECT_NEAR(s.com_W[2], model.standing_com_height_m(), 1e-5);
  EXPECT_EQ(s.link_names[static_cast<std::size_t>(s.foot_links[0])], model.links()[static_cast<std::size_t>(model.soles()[0].link)].name);
}

TEST(MotionViewer, MotionSceneIsTheRobotsForwardKinematics) {
  const RobotModel& model = humanoid25();
  FootLiftOptions lift;
  lift.fps = 30;
  lift.duration_s = 2.0;
  const Reference ref = foot_lift_reference(model, lift);
  const ViewerScene s = motion_scene(model, ref, "lift.csv");
  ASSERT_EQ(s.num_frames, ref.num_frames());
  EXPECT_EQ(s.fps, 30);
  EXPECT_EQ(s.title, model.name() + ": lift.csv");
  const std::size_t L = static_cast<std::size_t>(s.num_links());
  ASSERT_EQ(s.link_poses.size(), static_cast<std::size_t>(s.num_frames) * L * 7);
  ASSERT_EQ(s.contact[1], ref.contact[1]);
  EXPECT_TRUE(s.com_planned_W.empty());  // the synthetic reference has no plan
  // Every link pose equals FK of the reference's frame.
  const ReferenceRobotMap map(model, ref, "lift");
  RobotData data(model);
  for (int f : {0, 30, s.num_frames - 1}) {
    update_kinematics(model, data, map.q(ref, f));
    for (std::size_t l = 0; l < L; ++l) {
      const Iso3 X = link_pose(model, data, model.find_link(s.link_names[l]));
      const float* p = &s.link_poses[7 * (static_cast<std::size_t>(f) * L + l)];
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], X.translation()[k], 1e-6) << s.link_names[l];
      const Quat q(X.linear());
      EXPECT_NEAR(std::abs(q.coeffs().dot(Eigen::Vector4d(p[3], p[4], p[5], p[6]))), 1.0, 1e-6) << s.link_names[l];
    }
    const Vec3 com = com_position(model, data);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.com_W[3 * static_cast<std::size_t>(f) + k], com[k], 1e-6);
  }
  // A 120 Hz reference is shown at 60 Hz (ViewerOptions::max_fps): every 2nd frame.
  FootLiftOptions fast = lift;
  fast.fps = 120;
  const Reference ref120 = foot_lift_reference(model, fast);
  const ViewerScene s60 = motion_scene(model, ref120, "fast.csv");
  EXPECT_EQ(s60.fps, 60);
  EXPECT_EQ(s60.num_frames, (ref120.num_frames() + 1) / 2);
  ASSERT_EQ(s60.contact[1].size(), static_cast<std::size_t>(s60.num_frames));
  for (int k = 0; k < s60.num_frames; ++k) EXPECT_EQ(s60.contact[1][static_cast<std::size_t>(k)], ref120.contact[1][2 * static_cast<std::size_t>(k)]);
  const ReferenceRobotMap map120(model, ref120, "fast");
  update_kinematics(model, data, map120.q(ref120, 2 * 50));
  EXPECT_NEAR(s60.com_W[3 * 50 + 2], com_position(model, data).z(), 1e-6);
  ASSERT_FALSE(s60.notes.empty());
  EXPECT_EQ(s60.notes.back(), "shown at 60 Hz: every 2nd frame of the 120 Hz reference");
  ViewerOptions all;
  all.max_fps = 120;
  EXPECT_EQ(motion_scene(model, ref120, "fast.csv", all).num_frames, ref120.num_frames());
  // The lifted (right) foot's sole rises off the floor during the lift.
  const std::size_t mid = static_cast<std::size_t>(45);  // 1.5 s
  EXPECT_GT(s.sole_corners_W[24 * mid + 12 + 2], 0.03f);
  EXPECT_NEAR(s.sole_corners_W[24 * mid + 2], 0.0f, 1e-4);
}

TEST(MotionViewer, PageRoundTripsItsData) {
  const RobotModel& model = humanoid25();
  FootLiftOptions lift;
  lift.fps = 30;
  Reference ref = foot_lift_reference(model, lift);
  const int T = ref.num_frames();
  ref.com_W = Mat3X::Constant(3, T, 0.5);
  ref.cop_W = Eigen::Matrix2Xd::Constant(2, T, 0.01);
  ViewerScene s = motion_scene(model, ref, "lift.npz");
  // A skeleton with one missing landmark sample.
  std::array<LandmarkTrack, kLandmarkCount> tracks;
  for (Landmark l : {Landmark::Pelvis, Landmark::LeftHip, Landmark::LeftKnee}) {
    LandmarkTrack& t = tracks[static_cast<std::size_t>(index(l))];
    t.present = true;
    t.p_W = Mat3X::Random(3, 2 * T);
    t.state.assign(static_cast<std::size_t>(2 * T), SampleState::Measured);
  }
  tracks[static_cast<std::size_t>(index(Landmark::LeftKnee))].state[10] = SampleState::Missing;
  s.skeleton = skeleton_points(tracks, 60, s);
  const ViewerOptions options = fake_three_options();
  const std::string html = viewer_page_html(s, options);
  EXPECT_EQ(html.find("'</script>'"), std::string::npos);  // escaped inside the script
  EXPECT_NE(html.find("'<\\/script>'"), std::string::npos);
  EXPECT_NE(html.find("id=\"rt-status\""), std::string::npos);  // the error hook the browser test reads
  EXPECT_EQ(html.find("http://"), std::string::npos);  // nothing fetched
  EXPECT_EQ(html.find("https://"), std::string::npos);
  const ViewerScene r = parse_viewer_page(html, "lift.html");
  EXPECT_EQ(r.mode, s.mode);
  EXPECT_EQ(r.title, s.title);
  EXPECT_EQ(r.robot, "humanoid25");
  EXPECT_EQ(r.fps, s.fps);
  EXPECT_EQ(r.num_frames, T);
  EXPECT_EQ(r.link_names, s.link_names);
  EXPECT_EQ(r.link_poses, s.link_poses);  // float32 bit for bit
  ASSERT_EQ(r.meshes.size(), s.meshes.size());
  for (std::size_t i = 0; i < s.meshes.size(); ++i) {
    EXPECT_EQ(r.meshes[i].link, s.meshes[i].link);
    EXPECT_EQ(r.meshes[i].positions_L, s.meshes[i].positions_L);
    EXPECT_EQ(r.meshes[i].indices, s.meshes[i].indices);
    EXPECT_EQ(r.meshes[i].color, s.meshes[i].color);
  }
  EXPECT_EQ(r.foot_links, s.foot_links);
  EXPECT_EQ(r.sole_corners_W, s.sole_corners_W);
  EXPECT_EQ(r.contact, s.contact);
  EXPECT_EQ(r.com_W, s.com_W);
  EXPECT_EQ(r.com_planned_W, s.com_planned_W);
  EXPECT_EQ(r.cop_planned_W.size(), static_cast<std::size_t>(2 * T));
  EXPECT_FLOAT_EQ(r.cop_planned_W[1], 0.01f);
  EXPECT_EQ(r.skeleton.names, (std::vector<std::string>{"pelvis", "left_hip", "left_knee"}));
  EXPECT_EQ(r.skeleton.bones, (std::vector<std::array<int, 2>>{{0, 1}, {1, 2}}));
  EXPECT_EQ(r.skeleton.p_W, s.skeleton.p_W);
  // Reference frame 5 is source frame 10 (60 Hz tracks, 30 Hz reference): exact, and invalid.
  const LandmarkTrack& knee = tracks[static_cast<std::size_t>(index(Landmark::LeftKnee))];
  EXPECT_FLOAT_EQ(r.skeleton.p_W[3 * (5 * 3 + 2) + 1], static_cast<float>(knee.p_W(1, 10)));
  EXPECT_EQ(r.skeleton.valid[5 * 3 + 2], 0);
  EXPECT_EQ(r.skeleton.valid[6 * 3 + 2], 1);
  EXPECT_TRUE(r.landmarks.empty());
}

TEST(MotionViewer, BadInputsGiveLocatedErrors) {
  const RobotModel& model = humanoid25();
  Reference ref = constant_reference(model, model.standing_q(), 0.5, 30);
  ref.joint_names[3] = "no_such_joint";
  EXPECT_NE(error_of([&] { motion_scene(model, ref, "walk.csv"); }).find("walk.csv"), std::string::npos);
  // libjs-three missing: one line that names the package.
  ViewerOptions none;
  none.three_js_dir = "/nonexistent/three";
  const ViewerScene s = robot_scene(model);
  EXPECT_EQ(error_of([&] { viewer_page_html(s, none); }),
            "/nonexistent/three/three.min.js: not found; the viewer inlines three.js from the Debian package libjs-three "
            "(apt-get install libjs-three)");
  EXPECT_EQ(error_of([&] { require_three_js(none); }).find("/nonexistent/three/three.min.js"), 0u);
  // Pages that are not ours, or whose data was damaged.
  EXPECT_EQ(error_of([] { parse_viewer_page("<html></html>", "x.html"); }),
            "x.html: no viewer data block (not a page of retarget view)");
  const std::string html = viewer_page_html(s, fake_three_options());
  std::string cut = html;
  const std::size_t at = cut.find("\"link_poses\":\"") + 14;
  cut.erase(at, 4);  // one float fewer
  EXPECT_NE(error_of([&] { parse_viewer_page(cut, "x.html"); }).find("x.html [link_poses]: expected"), std::string::npos);
  std::string bad = html;
  bad.replace(bad.find("\"num_frames\":1"), 14, "\"num_frames\":0");
  EXPECT_EQ(error_of([&] { parse_viewer_page(bad, "x.html"); }), "x.html [num_frames]: expected at least 1");
  std::string syntax = html;
  syntax.replace(syntax.find("\"mode\":"), 7, "\"mode\";");
  EXPECT_NE(error_of([&] { parse_viewer_page(syntax, "x.html"); }).find("x.html:1:"), std::string::npos);
}

TEST(MotionViewer, TriangleBudgetDecimatesMeshes) {
  RT_REQUIRE_SHARED(g1, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");
  const auto model = RobotModel::load(test::source_path("robots/g1"));
  ViewerOptions small;
  small.max_triangles = 5000;
  const ViewerScene s = robot_scene(*model, small);
  EXPECT_EQ(s.mesh_source, "visual");
  EXPECT_LE(s.num_triangles(), 5000 + 12 * static_cast<int>(s.meshes.size()));
  EXPECT_GT(s.num_triangles(), 1500);
  ASSERT_FALSE(s.notes.empty());
  EXPECT_NE(s.notes.back().find("decimated"), std::string::npos);
}

TEST(MotionViewer, TenSecondG1PageFitsTenMegabytes) {
  RT_REQUIRE_SHARED(g1, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");
  ViewerOptions options;
  if (!std::filesystem::exists(options.three_js_dir + "/three.min.js"))
    GTEST_SKIP() << "libjs-three is not installed (apt-get install libjs-three)";
  const auto model = RobotModel::load(test::source_path("robots/g1"));
  Reference ref = constant_reference(*model, model->standing_q(), 10.0, 30);
  ref.com_W = Mat3X::Constant(3, ref.num_frames(), 0.6);
  ref.cop_W = Eigen::Matrix2Xd::Zero(2, ref.num_frames());
  const ViewerScene s = motion_scene(*model, ref, "walk.csv", options);
  EXPECT_EQ(s.num_frames, 301);
  const std::string html = viewer_page_html(s, options);
  EXPECT_LE(html.size(), 10u << 20) << html.size();
  EXPECT_GT(html.size(), 1u << 20);  // three.js itself is 0.85 MB
  EXPECT_EQ(parse_viewer_page(html, "walk.html").num_frames, 301);
}

}  // namespace
}  // namespace rt
