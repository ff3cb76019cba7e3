// ASF/AMC input (asf_amc.hpp, asf_motion.hpp).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "formats/asf/asf_amc.hpp"
#include "formats/bvh/bvh_kinematics.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/jobs/convert_job.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/motion/asf/asf_motion.hpp"
#include "retarget/motion/load_motion.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// A chain root -> a -> b with non-trivial axes, dof orders and a radians AMC.
const char* kAsf = R"(:version 1.10
:units
  length 1
  angle deg
:root
   order TX TY TZ RZ RX RY
   axis ZXY
   position 1 2 3
   orientation 0 0 0
:bonedata
  begin
     name a
     direction 1 0 0
     length 2
     axis 10 -30 45 ZYX
    dof rz rx ry
  end
  begin
     name b
     direction 0 0 1
     length 1.5
     axis 0 90 0 XYZ
    dof ry rx
  end
  begin
     name c
     direction 0 1 0
     length 1
     axis 0 0 0 XYZ
  end
:hierarchy
  begin
    root a
    a b
    b c
  end
)";

Mat3 rot(int axis, double a) { return AngleAxis(a, Vec3::Unit(axis)).toRotationMatrix(); }

TEST(AsfAmc, BvhEquivalentReproducesTheAcclaimKinematics) {
  const AsfSkeleton s = parse_asf(kAsf, "t.asf");
  ASSERT_EQ(s.bones.size(), 3u);
  const double d = M_PI / 180;
  const AmcMotion m = parse_amc(":FULLY-SPECIFIED\n:RADIANS\n1\nroot 0.5 1 -2 0.3 -0.2 0.7\na 0.1 0.2 -0.4\nb 0.6 -0.25\n", "t.amc", s);
  ASSERT_EQ(m.num_frames, 1);
  const BvhFile f = asf_amc_to_bvh(s, m, 1.0 / 120, "t.amc");
  BvhPose pose;
  bvh_forward_kinematics(f, 0, pose);
  // The Acclaim formulas written out: A = A_parent C M C^-1, rotations first-listed first.
  const Mat3 root_R = rot(1, 0.7) * rot(0, -0.2) * rot(2, 0.3);  // values RZ RX RY, applied z, x, y (axis ZXY)
  const Vec3 root_p(1 + 0.5, 2 + 1, 3 - 2);
  const Mat3 Ca = rot(0, 10 * d) * rot(1, -30 * d) * rot(2, 45 * d);  // ZYX: z first
  const Mat3 Ma = rot(1, -0.4) * rot(0, 0.2) * rot(2, 0.1);             // dof rz rx ry
  const Mat3 Aa = root_R * Ca * Ma * Ca.transpose();
  const Mat3 Cb = rot(2, 0) * rot(1, 90 * d) * rot(0, 0);
  const Mat3 Mb = rot(0, -0.25) * rot(1, 0.6);  // dof ry rx
  const Mat3 Ab = Aa * Cb * Mb * Cb.transpose();
  const Vec3 b_start = root_p + 2 * (Aa * Vec3::UnitX());
  const Vec3 c_start = b_start + 1.5 * (Ab * Vec3::UnitZ());
  EXPECT_LE((pose.p_F_joint.col(0) - root_p).norm(), 1e-12);
  EXPECT_LE((pose.p_F_joint.col(1) - root_p).norm(), 1e-12);  // a starts at the root
  EXPECT_LE((pose.p_F_joint.col(2) - b_start).norm(), 1e-12);
  EXPECT_LE((pose.p_F_joint.col(3) - c_start).norm(), 1e-12);
  EXPECT_LE((pose.R_F_joint[2] - Ab).norm(), 1e-12);
  // :DEGREES gives the same pose from degrees; the ASF's own unit applies without a keyword.
  std::ostringstream deg;
  deg.precision(17);
  deg << "1\nroot 0.5 1 -2 " << 0.3 / d << " " << -0.2 / d << " " << 0.7 / d << "\na " << 0.1 / d << " " << 0.2 / d << " "
      << -0.4 / d << "\nb " << 0.6 / d << " " << -0.25 / d << "\n";
  BvhPose pose2;
  bvh_forward_kinematics(asf_amc_to_bvh(s, parse_amc(deg.str(), "d.amc", s), 1.0 / 120, "d.amc"), 0, pose2);
  EXPECT_LE((pose2.p_F_joint - pose.p_F_joint).cwiseAbs().maxCoeff(), 1e-9);
  // A leaf's end is an End Site.
  ASSERT_EQ(f.end_sites.size(), 1u);
  EXPECT_EQ(f.end_sites[0].parent, 3);
}

TEST(AsfAmc, GimbalLockedBonesKeepTheirRotation) {
  const AsfSkeleton s = parse_asf(kAsf, "t.asf");
  // Pitch of exactly 90 degrees about y in the root (the decomposition's singular case).
  const AmcMotion m = parse_amc(":DEGREES\n1\nroot 0 0 0 30 40 90\na 0 90 0\nb 90 0\n", "g.amc", s);
  const BvhFile f = asf_amc_to_bvh(s, m, 1.0 / 120, "g.amc");
  BvhPose pose;
  bvh_forward_kinematics(f, 0, pose);
  const double d = M_PI / 180;
  const Mat3 root_R = rot(1, 90 * d) * rot(0, 40 * d) * rot(2, 30 * d);
  EXPECT_LE((pose.R_F_joint[0] - root_R).norm(), 1e-9);
}

struct Expectation {
  std::string where, message;
};

TEST(AsfAmcBadInput, EveryCorpusFileGivesItsOneLineLocatedError) {
  const std::string dir = test::source_path("tests/data/asf/bad");
  std::map<std::string, Expectation> manifest;
  std::ifstream in(dir + "/expected.tsv");
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string name, where, message;
    std::getline(fields, name, '\t');
    std::getline(fields, where, '\t');
    std::getline(fields, message);
    manifest[name] = {where, message};
  }
  ASSERT_GE(manifest.size(), 30u);
  const AsfSkeleton good = read_asf(dir + "/good.asf");
  EXPECT_EQ(read_amc(dir + "/good.amc", good).num_frames, 2);
  for (const auto& [name, e] : manifest) {
    SCOPED_TRACE(name);
    const std::string path = dir + "/" + name;
    try {
      if (name.size() > 4 && name.substr(name.size() - 4) == ".asf") {
        read_asf(path);
      } else {
        read_amc(path, good);
      }
      ADD_FAILURE() << "accepted";
    } catch (const InputError& x) {
      const std::string what = x.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_EQ(x.location(), path + ":" + e.where) << what;
      EXPECT_NE(x.message().find(e.message), std::string::npos) << what;
    }
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name != "expected.tsv" && name.rfind("good.", 0) != 0) {
      EXPECT_TRUE(manifest.count(name)) << "not in the manifest: " << name;
    }
  }
}

TEST(AsfAmcBadInput, TruncatedMotionsFailLocatedOrParse) {
  const std::string dir = test::source_path("tests/data/asf/bad");
  const AsfSkeleton good = read_asf(dir + "/good.asf");
  const std::string amc = read_file(dir + "/good.amc");
  const std::string asf = read_file(dir + "/good.asf");
  for (std::size_t n = 0; n < asf.size(); ++n) {
    try {
      parse_asf(asf.substr(0, n), "cut.asf");
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().rfind("cut.asf:", 0), 0u) << e.what();
    }
  }
  for (std::size_t n = 0; n < amc.size(); ++n) {
    try {
      parse_amc(amc.substr(0, n), "cut.amc", good);
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().rfind("cut.amc:", 0), 0u) << e.what();
    }
  }
}

TEST(AsfAmc, SkeletonFoundByCmuNamingOrGiven) {
  const std::string dir = test::scratch_dir();
  std::filesystem::create_directories(dir + "/a");
  write(dir + "/a/07.asf", kAsf);
  write(dir + "/a/07_02.amc", "1\n");
  EXPECT_EQ(find_asf_for(dir + "/a/07_02.amc", ""), dir + "/a/07.asf");
  write(dir + "/a/07_02.asf", kAsf);  // CMU naming first
  EXPECT_EQ(find_asf_for(dir + "/a/07_02.amc", ""), dir + "/a/07.asf");
  std::filesystem::create_directories(dir + "/b");
  write(dir + "/b/walk.amc", "1\n");
  write(dir + "/b/subject.asf", kAsf);  // the only one in the folder
  EXPECT_EQ(find_asf_for(dir + "/b/walk.amc", ""), dir + "/b/subject.asf");
  write(dir + "/b/other.asf", kAsf);
  try {
    find_asf_for(dir + "/b/walk.amc", "");
    ADD_FAILURE() << "two candidates accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("walk.asf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--asf"), std::string::npos) << e.what();
  }
  EXPECT_EQ(find_asf_for(dir + "/b/walk.amc", dir + "/b/other.asf"), dir + "/b/other.asf");
  EXPECT_THROW(find_asf_for(dir + "/b/walk.amc", dir + "/b/none.asf"), InputError);
}

// The CMU pair and the CMU BVH conversion of the same take (subject 01, trial 01) describe the
// same motion: after loading (units, up axis, floor, start alignment) the joint centres agree.
TEST(AsfAmcRealData, CmuPairMatchesTheBvhOfTheSameTake) {
  RT_REQUIRE_SHARED(amc, "bvh/cmu_asf_amc/01_01.amc");
  RT_REQUIRE_SHARED(bvh, "bvh/cmu_mb_01_01_forward_jumps_turn.bvh");
  const HumanMotion a = load_motion(amc);
  const HumanMotion b = load_motion(bvh);
  EXPECT_EQ(a.source.format, "asf/amc");
  EXPECT_EQ(a.source.profile, "cmu_asf");
  EXPECT_EQ(a.source.units, "cmu");
  EXPECT_EQ(a.source.up_axis, 'y');
  EXPECT_DOUBLE_EQ(a.fps, 120);
  ASSERT_EQ(a.num_frames, b.num_frames);  // the BVH's synthetic T-pose frame is dropped
  // The legs, pelvis, spine and chest agree to rounding; above the thorax the BVH conversion
  // starts the neck and clavicles at the thorax's start (their OFFSET is 0), the ASF at its end,
  // so those joints differ by exactly the thorax bone (2.06488 units = 0.1166 m), at every frame.
  const double thorax_m = 2.06488 * 0.0254 / 0.45;
  double worst_lower = 0, worst_upper_deviation = 0;
  for (int t = 0; t < a.num_frames; t += 5) {
    for (Landmark l : {Landmark::Pelvis, Landmark::Spine, Landmark::Chest, Landmark::LeftHip, Landmark::LeftKnee,
                       Landmark::LeftAnkle, Landmark::LeftToe, Landmark::RightKnee, Landmark::RightAnkle})
      worst_lower = std::max(worst_lower, (a[l].p_W.col(t) - b[l].p_W.col(t)).norm());
    for (Landmark l : {Landmark::Neck, Landmark::LeftShoulder, Landmark::LeftElbow, Landmark::RightWrist})
      worst_upper_deviation = std::max(worst_upper_deviation, std::abs((a[l].p_W.col(t) - b[l].p_W.col(t)).norm() - thorax_m));
  }
  EXPECT_LE(worst_lower, 1e-4);
  EXPECT_LE(worst_upper_deviation, 1e-4);
}

// The first 2 s of the CMU pair (beside its ASF) convert for every robot.
TEST(AsfAmcRealData, ConvertsForAllFourRobots) {
  RT_REQUIRE_SHARED(amc, "bvh/cmu_asf_amc/01_01.amc");
  RT_REQUIRE_SHARED(robots, "robots");
  const std::string dir = test::scratch_dir();
  std::filesystem::copy_file(test::shared_data("bvh/cmu_asf_amc/01.asf"), dir + "/01.asf");
  std::istringstream in(read_file(amc));
  std::string cut;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("241", 0) == 0 && line.find(' ') == std::string::npos) break;
    cut += line + "\n";
  }
  write(dir + "/01_01.amc", cut);
  for (const char* robot : {"humanoid25", "g1", "h1", "jvrc1"}) {
    SCOPED_TRACE(robot);
    const auto model = RobotModel::load(test::source_path(std::string("robots/") + robot));
    ConvertRequest request;
    request.clip_path = dir + "/01_01.amc";
    request.write_outputs = false;
    const ConvertResult r = run_convert(request, *model);
    EXPECT_EQ(r.clip.human.num_frames, 240);
    EXPECT_EQ(r.clip.reference.num_frames(), 60);
    EXPECT_EQ(r.quality.position_limit_violations, 0);
    EXPECT_LT(r.quality.landmark_error_median_m, 0.08);
    EXPECT_LE(r.quality.penetration_max_m, 0.005);
  }
}

}  // namespace
}  // namespace rt
