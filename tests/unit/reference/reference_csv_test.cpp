#include "formats/reference/reference_csv.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include "reference_test_util.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/reference/reference_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

CsvReadOptions options_for(const std::vector<std::string>& joints) {
  CsvReadOptions o;
  o.joint_names = joints;
  o.joints_source = "of robot g1";
  return o;
}

std::vector<std::string> cells_of(const std::string& text) {
  std::vector<std::string> cells;
  for (const std::string& line : split(text, "\n"))
    for (const std::string& c : split(line, ",")) cells.push_back(c);
  return cells;
}

TEST(ReferenceCsv, RoundTripIsBitExactAtStoredPrecision) {
  const auto joints = test::g1_joint_names();
  const Reference r = test::make_reference(50, joints, 7, false);
  const std::string first = format_reference_csv(r);
  const Reference back = parse_reference_csv(first, "walk.csv", options_for(joints));
  ASSERT_EQ(back.num_frames(), 50);
  // write -> read -> write is byte-identical
  Reference again = back;
  again.fps = 30;
  EXPECT_EQ(format_reference_csv(again), first);

  // Every value read equals the stored decimal exactly (the double strtod gives for it), in the
  // column order root x y z, qx qy qz qw, joints.
  const std::vector<std::string> cells = cells_of(first);
  ASSERT_EQ(cells.size(), 50u * (7 + joints.size()));
  std::size_t k = 0;
  for (int t = 0; t < 50; ++t) {
    const Quat& q = back.root_quat_W[static_cast<std::size_t>(t)];
    const double row[7] = {back.root_pos_W(0, t), back.root_pos_W(1, t), back.root_pos_W(2, t), q.x(), q.y(), q.z(), q.w()};
    for (double v : row) EXPECT_EQ(v, std::strtod(cells[k++].c_str(), nullptr)) << "cell " << k - 1;
    for (std::size_t j = 0; j < joints.size(); ++j)
      EXPECT_EQ(back.joint_pos(static_cast<Eigen::Index>(j), t), std::strtod(cells[k++].c_str(), nullptr));
  }
  // ...and within the 9-significant-digit rounding of the original.
  EXPECT_LT((back.joint_pos - r.joint_pos).cwiseAbs().maxCoeff(), 2 * 5e-9);
  EXPECT_LT((back.root_pos_W - r.root_pos_W).cwiseAbs().maxCoeff(), 5e-9);
  EXPECT_TRUE(std::signbit(back.joint_pos(1, 1)));  // -0 survives
}

TEST(ReferenceCsv, DocumentedNumberFormat) {
  Reference r;
  r.fps = 30;
  r.joint_names = {"a", "b", "c", "d"};
  r.root_pos_W = Mat3X(3, 1);
  r.root_pos_W.col(0) << 0.000545, -0.000051, 0.782845;
  r.root_quat_W = {Quat::Identity()};
  r.joint_pos = MatX(4, 1);
  r.joint_pos.col(0) << 1.5707963267948966, -1e-12, 123456789012.0, 0.1;
  EXPECT_EQ(format_reference_csv(r), "0.000545,-5.1e-05,0.782845,0,0,0,1,1.57079633,-1e-12,1.23456789e+11,0.1\n");
}

TEST(ReferenceCsv, AcceptsBomCrLfSpacesPlusSignAndTrailingBlankLines) {
  const std::string text = "\xEF\xBB\xBF" "0, 0 ,+0.5,0,0,0,1,0.25\r\n1,2,3,0,0,0,1,-1e-3\r\n\r\n\n";
  const Reference r = parse_reference_csv(text, "x.csv", options_for({"j"}));
  ASSERT_EQ(r.num_frames(), 2);
  EXPECT_EQ(r.root_pos_W(2, 0), 0.5);
  EXPECT_EQ(r.joint_pos(0, 1), -1e-3);
}

TEST(ReferenceCsv, NormalisesSmallQuaternionDeviationsAndKeepsExactOnes) {
  // 6-decimal quaternion as in the LAFAN1 files: norm off by ~1e-6 -> normalised.
  const std::string text = "0,0,0,0.001066,0.031608,-0.059077,0.997752,0\n0,0,0,0,0,0.6,0.8,0\n";
  const Reference r = parse_reference_csv(text, "x.csv", options_for({"j"}));
  EXPECT_NEAR(r.root_quat_W[0].norm(), 1.0, 1e-15);
  EXPECT_NE(r.root_quat_W[0].w(), 0.997752);
  EXPECT_EQ(r.root_quat_W[1].z(), 0.6);  // |q| = 1 up to rounding: kept as stored
  EXPECT_EQ(r.root_quat_W[1].w(), 0.8);
}

TEST(ReferenceCsv, BadInputIsOneLineErrorWithLocation) {
  const auto o = options_for({"j1", "j2"});
  auto parse = [&](const std::string& text) { return [text, o] { parse_reference_csv(text, "bad.csv", o); }; };
  test::expect_input_error(parse(""), {"bad.csv:1", "empty file"});
  test::expect_input_error(parse(" \n\n"), {"bad.csv:1", "empty file"});
  test::expect_input_error(parse("x,y,z,qx,qy,qz,qw,j1,j2\n0,0,0,0,0,0,1,0,0\n"), {"bad.csv:1:1", "header row"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0\n"),
                           {"bad.csv:1:", "expected 9 columns (7 root + 2 joints of robot g1), got 8"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0,0\n0,0,0,0,0,0,1,0,0,5\n"), {"bad.csv:2:", "expected 9 columns", "got 10"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0,0\n0,0,0\n"), {"bad.csv:2:", "got 3"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0,0\n0,0,0,0,0,0,1,nan,0\n"), {"bad.csv:2:15", "column 8 (j1)", "not a finite"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0,inf\n"), {"bad.csv:1:17", "column 9 (j2)"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0,1e999\n"), {"bad.csv:1:17", "not a finite"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0,0\n0,0,0,0,0,0,1,1.5x,0\n"), {"bad.csv:2:15", "'1.5x' is not a number"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,,0\n"), {"bad.csv:1:15", "column 8 (j1) is empty"});
  test::expect_input_error(parse("0,0,0,0,0,0,1,0,0\n\n0,0,0,0,0,0,1,0,0\n"), {"bad.csv:2", "empty row"});
  test::expect_input_error(parse("0,0,0,0,0,0,2,0,0\n"), {"bad.csv:1:7", "norm 2", "unit quaternion"});
  test::expect_input_error(parse("0,0,0,0,0,0,0,0,0\n"), {"bad.csv:1:7", "norm 0"});
}

TEST(ReferenceCsv, PlainCsvNeedsRateAndJoints) {
  const std::string dir = test::scratch_dir();
  write_file_atomic(dir + "/p.csv", "0,0,0.8,0,0,0,1,0.5\n");
  const Reference r = read_plain_csv(dir + "/p.csv", {"knee"}, 50, "toy");
  EXPECT_EQ(r.fps, 50);
  EXPECT_EQ(r.robot_name, "toy");
  EXPECT_FALSE(r.has_contacts());
  test::expect_input_error([&] { read_plain_csv(dir + "/p.csv", {"knee"}, 0); }, {"p.csv", "--fps"});
  test::expect_input_error([&] { read_plain_csv(dir + "/p.csv", {}, 30); }, {"p.csv", "--robot"});
  test::expect_input_error([&] { read_plain_csv(dir + "/p.csv", {"a", "b"}, 30, "toy"); },
                           {"p.csv:1", "expected 9 columns (7 root + 2 joints of robot toy), got 8"});
}

// The published third-party G1 references (shared/data/README.md §4).
struct RealClip {
  const char* name;  ///< test name suffix
  const char* path;
  double fps;
  int frames;
};
// Stable test names in ctest (gtest otherwise prints the struct's bytes, pointers included).
void PrintTo(const RealClip& clip, std::ostream* os) { *os << clip.path; }

class RealG1Csv : public ::testing::TestWithParam<RealClip> {};

TEST_P(RealG1Csv, ReadsWithG1JointOrder) {
  const RealClip clip = GetParam();
  RT_REQUIRE_SHARED(path, clip.path);
  ReferenceReadOptions o;
  o.robot_name = "g1";
  o.joint_names = test::g1_joint_names();
  o.fps = clip.fps;
  const Reference r = read_reference(path, o);
  EXPECT_EQ(r.num_frames(), clip.frames);
  EXPECT_EQ(r.fps, clip.fps);
  EXPECT_EQ(r.joint_pos.rows(), 29);
  EXPECT_EQ(r.robot_name, "g1");
  for (const Quat& q : r.root_quat_W) ASSERT_NEAR(q.norm(), 1.0, kQuatKeepNormTolerance);
  // Pelvis height plausible for G1 (README: 0.42-0.93 m on the fight clip).
  EXPECT_GT(r.root_pos_W.row(2).minCoeff(), 0.3);
  EXPECT_LT(r.root_pos_W.row(2).maxCoeff(), 1.0);
  EXPECT_LT(r.joint_pos.cwiseAbs().maxCoeff(), 3.2);

  // Their 6-decimal values survive our writer exactly (quaternions aside, which were normalised).
  const std::string text = read_file(path);
  const std::string first_line = text.substr(0, text.find('\n'));
  const std::vector<std::string> cells = split(first_line, ",");
  ASSERT_EQ(cells.size(), 36u);
  for (int j = 0; j < 29; ++j) EXPECT_EQ(r.joint_pos(j, 0), std::strtod(cells[7 + static_cast<std::size_t>(j)].c_str(), nullptr));
  const std::string ours = format_reference_csv(r);
  const Reference again = parse_reference_csv(ours, "ours.csv", options_for(o.joint_names));
  EXPECT_EQ(again.joint_pos, r.joint_pos);
  EXPECT_EQ(again.root_pos_W, r.root_pos_W);

  // The same file without --fps, or for a robot with another joint count, is refused clearly.
  ReferenceReadOptions no_fps = o;
  no_fps.fps = 0;
  test::expect_input_error([&] { read_reference(path, no_fps); }, {"--fps", "robot"});
  ReferenceReadOptions short_robot = o;
  short_robot.joint_names.pop_back();
  test::expect_input_error([&] { read_reference(path, short_robot); }, {":1", "expected 35 columns (7 root + 28 joints of robot g1), got 36"});
}

INSTANTIATE_TEST_SUITE_P(SharedData, RealG1Csv,
                         ::testing::Values(RealClip{"lafan1_fight1_subject2", "retargeted/g1_lafan1_unitree/fight1_subject2.csv", 30, 7347},
                                           RealClip{"g1_moves_J_Dance0_StepTouch", "retargeted/g1_moves/J_Dance0_StepTouch.csv", 60, 1949},
                                           RealClip{"g1_moves_B_HandsUp", "retargeted/g1_moves/B_HandsUp.csv", 60, 442}),
                         [](const ::testing::TestParamInfo<RealClip>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace rt
