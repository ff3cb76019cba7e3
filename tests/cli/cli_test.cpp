// The `retarget` tool end to end (README "Command line", "Exit codes"): each case runs the binary in
// a scratch folder and checks the exit status, the output and the files written.

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "formats/reference/npz_file.hpp"
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
  // Issue 18: a usage error is one line (CLI11 printed a second "Run with --help" line), naming the
  // command whose --help to read.
  for (const char* args : {"", "frobnicate", "convert", "convert a.bvh --fps", "validate", "convert a.bvh --fps abc",
                           "batch x", "inspect --robot"}) {
    r = run(dir, args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << args << ": " << r.err;
    EXPECT_EQ(r.err.find("Run with --help"), std::string::npos) << args << ": " << r.err;
  }
  r = run(dir, "convert a.bvh --fps abc");
  EXPECT_NE(r.err.find("(see 'retarget convert --help')"), std::string::npos) << r.err;
}

TEST(Cli, InspectRobotAndClip) {
  const std::string dir = test::scratch_dir();
  CliRun r = run(dir, "inspect '" + test::source_path("robots/humanoid25") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("robot humanoid25"), std::string::npos);
  EXPECT_NE(r.out.find("mass          51.00 kg"), std::string::npos);
  EXPECT_NE(r.out.find("standing hold stands"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("one foot      COM over the left sole: reached"), std::string::npos) << r.out;
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
  // odd_biped's legs have three pitch joints and no roll joint, so its COM cannot move sideways over
  // one sole: the one-foot warnings are true, and they are the only warnings.
  EXPECT_NE(r.out.find("checks        2 warning(s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cannot be brought over the left sole"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cannot be brought over the right sole"), std::string::npos) << r.out;
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

// The progress line (README "Progress"): on a terminal (a pseudo-terminal from util-linux's
// `script`) the check shows the clip time simulated of the total with an ETA, redrawn in place;
// with stderr in a file (a pipe, a batch worker's log) nothing. The 2 s delay is set to 0 here.
TEST(Cli, ProgressLineOnlyOnATerminal) {
  if (std::system("script -qec true /dev/null > /dev/null 2>&1") != 0) GTEST_SKIP() << "no util-linux script (pseudo-terminal)";
  const std::string dir = test::scratch_dir();
  const std::string robot = "--robot '" + test::source_path("robots/humanoid25") + "'";
  // A 69.7 s reference (the clip played 20 times slower): a check of about 2 s here.
  CliRun r = run(dir, "convert '" + test::source_path("examples/clips/foot_lift.bvh") + "' " + robot +
                          " --time-scale 20 --no-refine -o slow.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string cmd = "cd '" + dir + "' && RETARGET_PROGRESS_DELAY_MS=0 script -qec \"'" RT_RETARGET_BIN "' validate slow.csv " +
                          robot + "\" /dev/null > tty.txt 2>&1";
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw)) << raw;
  const std::string tty = read_file(dir + "/tty.txt");
  EXPECT_NE(tty.find("\r\033[Kchecking slow.csv: "), std::string::npos) << tty;
  EXPECT_NE(tty.find(" s of the clip simulated  "), std::string::npos) << tty;
  EXPECT_NE(tty.find(", ETA "), std::string::npos) << tty;
  EXPECT_NE(tty.find("/69.7 s of the clip simulated"), std::string::npos) << tty;  // the clip duration

  // The same without a terminal: not a byte of it.
  r = run(dir, "validate slow.csv " + robot);
  EXPECT_TRUE(r.status == 0 || r.status == 1) << r.err;
  EXPECT_EQ(r.err.find("elapsed"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  r = run(dir, "convert '" + test::source_path("examples/clips/foot_lift.bvh") + "' " + robot + " --no-refine -o again.csv");
  EXPECT_EQ(r.err.find("elapsed"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("contradicted by the data"), std::string::npos) << r.err;  // a normal clip: no rate warning
}

// The CMU Daz salsa clip states 120 Hz for 60 Hz data; at twice its speed it is still plausible
// human motion, so no contradiction is claimed, but the cgspeed conversions' 120 Hz gets a note
// naming --source-fps 60. Its data: no repeated frames, the landmarks' centre falls at most ~1 g.
TEST(Cli, CmuSalsaClipGetsTheSourceFpsHint) {
  RT_REQUIRE_SHARED(salsa, "bvh/cmu_daz_salsa_10.bvh");
  const std::string dir = test::scratch_dir();
  CliRun r = run(dir, "inspect '" + salsa + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string all = r.out + r.err;
  EXPECT_NE(all.find("some CMU subjects were captured at 60 Hz"), std::string::npos) << all;
  EXPECT_NE(all.find("pass --source-fps 60"), std::string::npos) << all;
  EXPECT_EQ(all.find("contradicted by the data"), std::string::npos) << all;
  r = run(dir, "inspect '" + salsa + "' --source-fps 60");
  EXPECT_EQ((r.out + r.err).find("pass --source-fps 60"), std::string::npos) << r.out << r.err;
}

// Bad references for validate (issue 5): each a one-line error and exit 2.
// The NPZ's body axis and joint columns in the simulator's order (--npz-layout, robot.yaml
// npz_layout), and validate refusing an NPZ that does not name its joints unless told the order.
TEST(Cli, NpzLayoutsAndValidateJointOrder) {
  RT_REQUIRE_SHARED(mjlab, "robots/unitree_g1/mjlab/g1.xml");
  const std::string dir = test::scratch_dir();
  const std::string clip = "'" + test::source_path("examples/clips/foot_lift.bvh") + "'";
  const std::string g1 = " --robot '" + test::source_path("robots/g1") + "'";
  const auto bodies = [&](const std::string& npz) {
    const npz::NpzFile f = npz::read_npz(dir + "/" + npz);
    return f.find("body_names")->to_strings();
  };
  CliRun r = run(dir, "convert " + clip + g1 + " -o default.npz --format npz --no-com-plan");
  ASSERT_EQ(r.status, 0) << r.err;
  // Exactly the keys README "Files out" lists as always written (com-plan adds com_pos_w, zmp_w
  // and cop_ref_w).
  std::vector<std::string> keys;
  for (const npz::NamedArray& a : npz::read_npz(dir + "/default.npz").arrays) keys.push_back(a.key);
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(keys, (std::vector<std::string>{"body_ang_vel_w", "body_lin_vel_w", "body_names", "body_pos_w", "body_quat_w",
                                            "contacts", "fps", "joint_names", "joint_pos", "joint_vel", "root_pos_w",
                                            "root_quat_w"}));
  const std::vector<std::string> mj = bodies("default.npz");  // G1's default: mjlab's order
  ASSERT_EQ(mj.size(), 30u);
  EXPECT_EQ(mj[0], "pelvis");
  EXPECT_EQ(mj[15], "torso_link");
  EXPECT_NE(read_file(dir + "/default.meta.json").find("\"npz_layout\": \"names:"), std::string::npos);
  r = run(dir, "convert " + clip + g1 + " -o mjcf.npz --format npz --npz-layout 'mjcf:" + mjlab + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(bodies("mjcf.npz"), mj);
  r = run(dir, "convert " + clip + g1 + " -o urdf.npz --format npz --npz-layout urdf");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(bodies("urdf.npz").size(), 39u);
  EXPECT_EQ(bodies("urdf.npz")[1], "pelvis_contour_link");
  r = run(dir, "convert " + clip + g1 + " -o x.npz --format npz --npz-layout isaac");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--npz-layout"), std::string::npos) << r.err;

  // As BeyondMimic writes it: no joint_names (and no meta.json beside it).
  npz::NpzFile f = npz::read_npz(dir + "/default.npz");
  std::vector<npz::NamedArray> bare;
  for (const npz::NamedArray& a : f.arrays)
    if (a.key != "joint_names") bare.push_back(a);
  write_file_atomic(dir + "/bare.npz", npz::encode_npz(bare));
  r = run(dir, "validate bare.npz" + g1);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("bare.npz [joint_names.npy]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--joint-order"), std::string::npos) << r.err;
  r = run(dir, "validate bare.npz" + g1 + " --joint-order '" + mjlab + "'");
  EXPECT_TRUE(r.status == 0 || r.status == 1) << r.status << " " << r.err;
  EXPECT_NE(r.out.find("bare.npz"), std::string::npos) << r.out;
}

TEST(Cli, OutputExtensionSelectsTheFormat) {
  const std::string dir = test::scratch_dir();
  const std::string clip = "'" + test::source_path("examples/clips/foot_lift.bvh") + "'";
  CliRun r = run(dir, "convert " + clip + " -o refs/walk.npz");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/refs/walk.npz"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/refs/walk.csv"));
  // The default robot is announced.
  EXPECT_NE(r.err.find("robot: humanoid25 (default; pass --robot)"), std::string::npos) << r.err;
  r = run(dir, "convert " + clip + " -o refs/b.CSV --robot humanoid25");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/refs/b.csv") || std::filesystem::exists(dir + "/refs/b.CSV"));
  EXPECT_EQ(r.err.find("(default; pass --robot)"), std::string::npos) << r.err;
  r = run(dir, "convert " + clip + " -o refs/both.npz --format csv,npz");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/refs/both.csv") && std::filesystem::exists(dir + "/refs/both.npz"));
  for (const std::string& bad : {std::string("-o x.pkl"), std::string("-o x.npz --format csv")}) {
    r = run(dir, "convert " + clip + " " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("error: -o x."), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.pkl.csv"));
  }
}

TEST(Cli, GuardsForUnitsFrameRateAndTypos) {
  const std::string dir = test::scratch_dir();
  const std::string clip_path = test::source_path("examples/clips/foot_lift.bvh");
  const std::string clip = "'" + clip_path + "' --robot humanoid25";
  // A cm clip read as metres: a 164 m person is an error, not a warning.
  CliRun r = run(dir, "convert " + clip + " --source-units m");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("implausible stature 164 m with units m (from --source-units)"), std::string::npos) << r.err;
  r = run(dir, "convert " + clip + " --source-units m --force -o forced");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("implausible stature"), std::string::npos) << r.err;  // still said, as a warning

  // Every frame twice and the rate doubled: the data says half the stated rate.
  std::string text = read_file(clip_path);
  const std::size_t motion = text.find("Frame Time:");
  ASSERT_NE(motion, std::string::npos);
  const std::size_t rows = text.find('\n', motion) + 1;
  std::string doubled = text.substr(0, rows);
  std::istringstream in(text.substr(rows));
  int frames = 0;
  for (std::string row; std::getline(in, row);)
    if (!row.empty()) doubled += row + "\n" + row + "\n", ++frames;
  const std::size_t count = doubled.find("Frames:");
  doubled.replace(count, doubled.find('\n', count) - count, "Frames: " + std::to_string(2 * frames));
  const std::size_t time = doubled.find("Frame Time:");
  doubled.replace(time, doubled.find('\n', time) - time, "Frame Time: 0.00833333");
  write(dir + "/doubled.bvh", doubled);
  r = run(dir, "convert doubled.bvh --robot humanoid25");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("frame rate 120 Hz contradicted by the data: every 2nd frame repeats its predecessor"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("likely 60 Hz); pass --source-fps 60 if so"), std::string::npos) << r.err;
  r = run(dir, "convert doubled.bvh --robot humanoid25 --source-fps 120");
  EXPECT_EQ(r.err.find("--source-fps 60"), std::string::npos) << r.err;

  // Mistyped options get the closest real one.
  r = run(dir, "convert " + clip + " --robto g1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown option '--robto' (did you mean '--robot'?)"), std::string::npos) << r.err;
  r = run(dir, "validate x.csv --jont-order=a.xml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown option '--jont-order' (did you mean '--joint-order'?)"), std::string::npos) << r.err;
  r = run(dir, "convert " + clip + " --zzzzzz");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown option '--zzzzzz'"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("did you mean"), std::string::npos) << r.err;
}

TEST(Cli, AsfAmcConvertsAndBadFilesExit2) {
  const std::string dir = test::scratch_dir();
  const std::string bad = test::source_path("tests/data/asf/bad");
  std::filesystem::copy_file(bad + "/good.asf", dir + "/02.asf");
  std::filesystem::copy_file(bad + "/good.amc", dir + "/02_01.amc");
  // A two-bone leg is not a recognised skeleton: the error says so (exit 2), but only after the
  // ASF was found by CMU naming and both files read.
  CliRun r = run(dir, "convert 02_01.amc --robot humanoid25");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.find("no skeleton for this AMC"), std::string::npos) << r.err;
  std::filesystem::copy_file(bad + "/frame_gap.amc", dir + "/03_01.amc");
  r = run(dir, "convert 03_01.amc --robot humanoid25 --asf 02.asf");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("03_01.amc:7:1: frame number 3 where 2 is expected"), std::string::npos) << r.err;
  std::filesystem::create_directories(dir + "/alone");
  std::filesystem::copy_file(bad + "/good.amc", dir + "/alone/03_01.amc");
  r = run(dir, "convert alone/03_01.amc --robot humanoid25");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("03.asf or 03_01.asf"), std::string::npos) << r.err;
  r = run(dir, "convert 02.asf --robot humanoid25");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("this is an ASF skeleton"), std::string::npos) << r.err;
}

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

// Issue 18 items 1-3 and 10: hostile rates, durations and pass options are one-line usage errors
// (exit 2) that state the valid range in words, never a crash, hang or huge allocation.
TEST(Cli, HostileRatesAndOptionsExit2WithTheRangeInWords) {
  const std::string dir = test::scratch_dir();
  const std::string robot = "--robot '" + test::source_path("robots/humanoid25") + "'";
  std::string row = "0,0,0.79,0,0,0,1";
  for (int j = 0; j < 25; ++j) row += ",0";
  std::string csv;
  for (int t = 0; t < 105; ++t) csv += row + "\n";
  write(dir + "/ref.csv", csv);
  auto expect_usage = [&](const std::string& args, const std::string& says) {
    const CliRun r = run(dir, args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << ": " << r.err;
    EXPECT_LE(r.err.size(), 200u) << args << ": " << r.err;  // no 309-digit numbers
  };
  for (const char* fps : {"1e300", "1e11", "1e9", "0.01", "inf", "nan", "-1"})
    expect_usage("validate ref.csv --fps " + std::string(fps) + " " + robot, "between 1 and 10000 Hz");
  const std::string clip = "'" + test::source_path("examples/clips/foot_lift.bvh") + "'";
  expect_usage("convert " + clip + " " + robot + " --fps 1e300", "between 1 and 1000 Hz");
  expect_usage("convert " + clip + " " + robot + " --source-fps 1e-6", "between 1 and 10000 Hz");
  expect_usage("convert " + clip + " " + robot + " --time-scale 1e300", "between 0.05 and 20");
  expect_usage("inspect " + clip + " --source-fps 0", "between 1 and 10000 Hz");
  expect_usage("batch x -o out " + robot + " --memory-limit 1e300", "between 0 and 16777216 MiB");
  expect_usage("batch x -o out " + robot + " -j 1e300", "between 1 and 1024");

  // A meta.json with an absurd or a duplicate "fps" (the last one silently won).
  const CliRun conv = run(dir, "convert " + clip + " " + robot + " -o lift --no-refine");
  ASSERT_EQ(conv.status, 0) << conv.err;
  const std::string meta = read_file(dir + "/lift.meta.json");
  const auto at = meta.find("\"fps\":");
  ASSERT_NE(at, std::string::npos);
  write(dir + "/dup.csv", read_file(dir + "/lift.csv"));
  write(dir + "/dup.meta.json", meta.substr(0, at) + "\"fps\": 0.001, " + meta.substr(at));
  const std::string fps_line = std::to_string(1 + std::count(meta.begin(), meta.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  expect_usage("validate dup.csv " + robot, "dup.meta.json:" + fps_line + ":");
  expect_usage("validate dup.csv " + robot, "fps: duplicate key (first at line " + fps_line + ")");
  write(dir + "/slow.csv", read_file(dir + "/lift.csv"));
  std::string slow = meta;
  slow.replace(at, slow.find_first_of(",\n", at) - at, "\"fps\": 0.001");
  write(dir + "/slow.meta.json", slow);
  expect_usage("validate slow.csv " + robot, "slow.meta.json [fps]: the frame rate is 0.001 Hz, not between 1 and 10000 Hz");

  // BVH Frame Time of 1000 s and 100 s (3.4 GB and a 238 MB CSV before).
  std::string bvh = read_file(test::source_path("examples/clips/foot_lift.bvh"));
  const auto ft = bvh.find("Frame Time:");
  ASSERT_NE(ft, std::string::npos);
  for (const char* t : {"1000", "100"}) {
    write(dir + "/slow.bvh", bvh.substr(0, ft) + "Frame Time: " + t + bvh.substr(bvh.find('\n', ft)));
    expect_usage("convert slow.bvh " + robot + " --no-refine -o slow", "slow.bvh:");
  }

  // Pipelines missing a pass, and pass options that size work.
  for (const char* passes : {"refine", "ik", "ground", "resample", "com-replan", "com-plan"})
    expect_usage("convert " + clip + " " + robot + " --passes " + passes, "--passes: ");
  expect_usage("convert " + clip + " " + robot + " --passes 'scale,ik,com-replan{period=1e-9}'",
               "option period: 1e-09 is not between 0.001 and 0.1 s");
  expect_usage("convert " + clip + " " + robot + " --passes 'scale,ik,resample{fps=1e300}'",
               "option fps: 1e+300 is not between 1 and 1000 Hz");
}

// Issue 18 items 6 and 8: FIFOs, devices and folders are refused up front (a FIFO blocked every
// reader, /dev/zero was "empty", `inspect` said "robot not found"); a write past the file-size
// limit (SIGXFSZ killed the process) is an error that leaves no temporary behind.
TEST(Cli, FifosDevicesFoldersAndFileSizeLimit) {
  const std::string dir = test::scratch_dir();
  const std::string robot = "--robot '" + test::source_path("robots/humanoid25") + "'";
  ASSERT_EQ(::mkfifo((dir + "/clip.bvh").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo((dir + "/robot.yaml").c_str(), 0644), 0);
  std::filesystem::create_directories(dir + "/empty_folder");
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {"convert clip.bvh " + robot, "clip.bvh: is a FIFO (named pipe)"},
           {"inspect clip.bvh", "clip.bvh: is a FIFO (named pipe)"},
           {"inspect robot.yaml", "robot.yaml: is a FIFO (named pipe)"},
           {"inspect empty_folder", "the folder holds no robot.yaml"},
           {"convert /dev/zero " + robot, "/dev/zero: is a character device"},
           {"validate clip.bvh " + robot, "clip.bvh"}}) {
    const CliRun r = run(dir, args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << ": " << r.err;
  }
  // ulimit -f 8 (4 KiB blocks of 512 bytes): the CSV does not fit.
  const std::string cmd = "cd '" + dir + "' && ulimit -f 8 && '" RT_RETARGET_BIN "' convert '" +
                          test::source_path("examples/clips/foot_lift.bvh") + "' " + robot +
                          " --no-refine -o out/lift > /dev/null 2> small.txt";
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw)) << "killed by a signal";
  EXPECT_EQ(WEXITSTATUS(raw), 2);
  const std::string err = read_file(dir + "/small.txt");
  EXPECT_NE(err.find("cannot write: File too large"), std::string::npos) << err;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/out"))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

// Issue 18 item 9: a batch worker checks its paths where it opens them (the batch passes the
// hidden --input-root / --output-root): a clip or manifest profile that resolves outside the input
// root, or an output folder that leads outside -o through a symlink, is exit 2 with one line, and
// nothing is written outside.
TEST(Cli, WorkerPathsAreCheckedWhereTheyAreOpened) {
  namespace fs = std::filesystem;
  const std::string dir = test::scratch_dir();
  const std::string robot = "--robot '" + test::source_path("robots/humanoid25") + "'";
  fs::create_directories(dir + "/in");
  fs::create_directories(dir + "/elsewhere");
  fs::create_directories(dir + "/out");
  fs::copy_file(test::source_path("examples/clips/foot_lift.bvh"), dir + "/elsewhere/lift.bvh");
  fs::copy_file(test::source_path("examples/clips/foot_lift.bvh"), dir + "/in/lift.bvh");
  write(dir + "/elsewhere/profile.yaml", "name: p\nbase: auto\n");
  fs::create_symlink(dir + "/elsewhere/lift.bvh", dir + "/in/escape.bvh");
  fs::create_symlink(dir + "/elsewhere/profile.yaml", dir + "/in/profile.yaml");
  fs::create_symlink(dir + "/elsewhere", dir + "/out/linked");
  const std::string in = " --input-root '" + dir + "/in'";
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {"convert in/escape.bvh" + in, "in/escape.bvh: resolves outside the input root"},
           {"convert in/lift.bvh --skeleton-profile in/profile.yaml --confine-profile" + in,
            "in/profile.yaml: resolves outside the input root"},
           {"convert in/lift.bvh -o out/linked/lift.csv --output-root '" + dir + "/out'",
            "leads outside the output folder"}}) {
    const CliRun r = run(dir, args + " " + robot + " --no-refine");
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << ": " << r.err;
  }
  int outside = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir + "/elsewhere")) ++outside;
  EXPECT_EQ(outside, 2);  // lift.bvh and profile.yaml only
  // Without the confinement (a plain convert) the same files are read: it is the worker's rule.
  EXPECT_EQ(run(dir, "convert in/escape.bvh -o plain.csv " + robot + " --no-refine").status, 0);
  // Inside the roots the worker converts as usual.
  const CliRun ok = run(dir, "convert in/lift.bvh -o out/lift.csv --output-root '" + dir + "/out'" + in + " " + robot +
                                 " --no-refine");
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_TRUE(fs::exists(dir + "/out/lift.csv"));
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
