// The `retarget` tool end to end (README "Command line", "Exit codes"): each case runs the binary in
// a scratch folder and checks the exit status, the output and the files written.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "retarget/core/file_io.hpp"
#include "retarget/report/check_report.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

struct CliRun {
  int status = -1;
  std::string out, err;
};

CliRun run(const std::string& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir + "' && '" RT_RETARGET_BIN "' " + args + " > out.txt 2> err.txt";
  const int raw = std::system(cmd.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = read_file(dir + "/out.txt");
  r.err = read_file(dir + "/err.txt");
  return r;
}

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

TEST(Cli, VersionHelpAndUsageErrors) {
  const std::string dir = test::scratch_dir();
  CliRun r = run(dir, "--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("retarget "), std::string::npos);
  r = run(dir, "");
  EXPECT_EQ(r.status, 2);
  r = run(dir, "convert --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("--robot"), std::string::npos);
  r = run(dir, "frobnicate");
  EXPECT_EQ(r.status, 2);
}

TEST(Cli, InspectRobotAndClip) {
  const std::string dir = test::scratch_dir();
  CliRun r = run(dir, "inspect '" + test::source_path("robots/humanoid25") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("robot humanoid25"), std::string::npos);
  EXPECT_NE(r.out.find("mass          51.00 kg"), std::string::npos);
  EXPECT_NE(r.out.find("standing hold stands"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("checks        0 warning(s)"), std::string::npos) << r.out;
  // The generated MuJoCo model, for MuJoCo's own tools.
  r = run(dir, "inspect '" + test::source_path("tests/data/urdf/odd_biped") + "' --mjcf model/odd.xml");
  EXPECT_EQ(r.status, 2) << r.err;  // the folder does not exist: one line, exit 2
  EXPECT_EQ(lines(r.err), 1) << r.err;
  std::filesystem::create_directories(dir + "/model");
  r = run(dir, "inspect '" + test::source_path("tests/data/urdf/odd_biped") + "' --mjcf model/odd.xml");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/model/odd.xml"));
  r = run(dir, "inspect '" + test::source_path("examples/clips/foot_lift.bvh") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("format        bvh"), std::string::npos);
  EXPECT_NE(r.out.find("units         cm"), std::string::npos);
}

TEST(Cli, InitRobotWritesALoadableConfig) {
  const std::string dir = test::scratch_dir();
  const std::string urdf = "'" + test::source_path("tests/data/urdf/odd_biped/odd_biped.urdf") + "'";
  const std::string pkg = " --package-path '" + test::source_path("tests/data/urdf") + "'";
  CliRun r = run(dir, "init-robot " + urdf + pkg + " -o odd");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("forward = root -x, up = root z"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("checks        0 warning(s)"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/odd/robot.yaml"));
  r = run(dir, "inspect odd");
  EXPECT_EQ(r.status, 0) << r.err;
  // An existing robot.yaml is kept unless --force; a missing URDF is bad input. One line, exit 2.
  r = run(dir, "init-robot " + urdf + pkg + " -o odd");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  EXPECT_EQ(run(dir, "init-robot " + urdf + pkg + " -o odd --force").status, 0);
  r = run(dir, "init-robot nope.urdf -o x");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

TEST(Cli, BadInputIsOneLineWithLocationAndExit2) {
  const std::string dir = test::scratch_dir();
  write(dir + "/bad.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Xposition Yposition Wrotation\n}\n");
  CliRun r = run(dir, "inspect bad.bvh");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("bad.bvh:5:"), std::string::npos) << r.err;
  r = run(dir, "inspect no_such_robot");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  r = run(dir, "convert bad.bvh --robot '" + test::source_path("robots/humanoid25") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

TEST(Cli, ConvertThenValidateWithReport) {
  const std::string dir = test::scratch_dir();
  const std::string robot = "--robot '" + test::source_path("robots/humanoid25") + "'";
  CliRun r = run(dir, "convert '" + test::source_path("examples/clips/foot_lift.bvh") + "' " + robot +
                       " -o out/lift --format csv,npz --no-refine");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("landmarks   error median"), std::string::npos);
  for (const char* f : {"out/lift.csv", "out/lift.npz", "out/lift.meta.json"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  r = run(dir, "validate out/lift.csv " + robot + " --report out/lift.report");
  EXPECT_TRUE(r.status == 0 || r.status == 1) << r.status << " " << r.err;
  const CheckReportSummary s = read_check_report(dir + "/out/lift.report/report.json");
  EXPECT_EQ(s.passed, r.status == 0);
  for (const char* f : {"report.txt", "com_cop_x.svg", "com_cop_y.svg", "contacts.svg", "tracking.svg"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/lift.report/" + f)) << f;
}

// Bad references for validate (issue 5): each a one-line error and exit 2.
TEST(Cli, ValidateRejectsBadReferences) {
  const std::string dir = test::scratch_dir();
  const std::string robot = "--robot '" + test::source_path("robots/humanoid25") + "'";
  std::string row = "0,0,0.79,0,0,0,1";
  for (int j = 0; j < 25; ++j) row += ",0";
  write(dir + "/header.csv", "x,y,z,qx,qy,qz,qw\n" + row + "\n");
  write(dir + "/columns.csv", row + ",0\n" + row + ",0\n");
  write(dir + "/nan.csv", row + "\n" + row.substr(0, row.size() - 1) + "nan\n");
  write(dir + "/ok.csv", row + "\n" + row + "\n");
  for (const char* f : {"header.csv", "columns.csv", "nan.csv"}) {
    const CliRun r = run(dir, std::string("validate ") + f + " --fps 30 " + robot);
    EXPECT_EQ(r.status, 2) << f << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << f << ": " << r.err;
    EXPECT_NE(r.err.find(f), std::string::npos) << r.err;
  }
  const CliRun no_fps = run(dir, "validate ok.csv " + robot);
  EXPECT_EQ(no_fps.status, 2);
  EXPECT_NE(no_fps.err.find("--fps"), std::string::npos) << no_fps.err;
  // Joint count of another robot: the G1 has 29 joints.
  std::string g1_row = "0,0,0.79,0,0,0,1";
  for (int j = 0; j < 29; ++j) g1_row += ",0";
  write(dir + "/g1.csv", g1_row + "\n" + g1_row + "\n");
  const CliRun wrong = run(dir, "validate g1.csv --fps 30 " + robot);
  EXPECT_EQ(wrong.status, 2);
  EXPECT_EQ(lines(wrong.err), 1) << wrong.err;
}

// Third-party G1 references (issue 5): validate runs to completion and writes a report that parses;
// a fall is a legitimate result, a crash or NaN is not.
class ThirdPartyG1 : public ::testing::TestWithParam<std::pair<const char*, int>> {};

TEST_P(ThirdPartyG1, ValidateCompletesWithAReport) {
  RT_REQUIRE_SHARED(csv, GetParam().first);
  RT_REQUIRE_SHARED(g1, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");
  const std::string dir = test::scratch_dir();
  const CliRun r = run(dir, "validate '" + csv + "' --robot '" + test::source_path("robots/g1") + "' --fps " +
                             std::to_string(GetParam().second) + " --report report");
  EXPECT_TRUE(r.status == 0 || r.status == 1) << r.status << " " << r.err;
  const CheckReportSummary s = read_check_report(dir + "/report/report.json");
  EXPECT_EQ(s.passed, r.status == 0);
  EXPECT_TRUE(std::isfinite(s.joint_rms_error_rad));
  std::cout << GetParam().first << ": " << r.out.substr(0, r.out.find('\n')) << "\n";
}

INSTANTIATE_TEST_SUITE_P(SharedData, ThirdPartyG1,
                         ::testing::Values(std::pair{"retargeted/g1_moves/B_HandsUp.csv", 60},
                                           std::pair{"retargeted/g1_moves/J_Dance0_StepTouch.csv", 60},
                                           std::pair{"retargeted/g1_lafan1_unitree/fight1_subject2.csv", 30}));

}  // namespace
}  // namespace rt
