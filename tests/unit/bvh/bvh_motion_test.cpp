// BVH -> HumanMotion: every real clip (profile, rate, units, up axis, T-pose, landmarks, stature,
// floor contact), synthetic clips (no shared data needed) and the load options.
//
// Stature, as used here and reported in source.details["stature_m"]: height above the estimated
// floor of the head joint (skull base / top of the neck in every built-in convention) at the first
// kept frame, divided by 0.87 (head height ~0.13 of stature, Drillis & Contini). Head End Sites are
// not used: several conventions have none (Daz, iClone) or a zero-length one (Bandai), and CMU's
// stops short of the crown. It must come out between 1.4 and 2.0 m for every clip (issue 3).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "bvh_test_clips.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

using L = Landmark;

struct ClipFacts {
  const char* file;
  const char* profile;
  const char* units;
  double fps;
  int file_frames;
  int dropped;
  std::set<Landmark> absent;  // heels are absent everywhere and not listed
};

// Facts from ../shared/data/README.md, checked against the data (the README says the iClone clip
// has a prepended T-pose; its frame 0 has the arms down and no pose jump, so nothing is dropped).
const std::vector<ClipFacts> kClips = {
    {"bandai1_dance-short_normal_001.bvh", "bandai_namco", "cm", 30, 1901, 0, {L::LeftHand, L::RightHand}},
    {"bandai2_walk-turn-left_normal_001.bvh", "bandai_namco", "cm", 30, 102, 0, {L::LeftHand, L::RightHand}},
    {"cmu_daz_martial_04.bvh", "cmu_daz", "cm", 120, 1317, 1, {}},
    {"cmu_daz_salsa_10.bvh", "cmu_daz", "cm", 120, 1198, 1, {}},
    {"cmu_iclone_07_01_walk.bvh", "iclone_cc_base", "cm", 60, 157, 0, {}},
    {"cmu_max_131_01_start_walk_stop.bvh", "cmu_3dsmax", "cmu", 120, 994, 0, {}},
    {"cmu_max_131_03_start_hop_stop_scaled_m.bvh", "cmu_3dsmax", "m", 120, 1248, 0, {}},
    {"cmu_mb_01_01_forward_jumps_turn.bvh", "cmu_motionbuilder_2008", "cmu", 120, 2752, 1, {}},
    {"lafan1_dance1_subject2.bvh", "lafan1", "cm", 30, 3945, 0, {L::LeftHand, L::RightHand}},
    {"games105_walk_and_turn_left.bvh", "games105", "m", 100, 420, 0, {}},
    {"pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh", "mixamo", "inch", 120, 1064, 0, {L::Neck}},
};

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

bool has_diagnostic(const HumanMotion& m, const std::string& text) {
  for (const Diagnostic& d : m.diagnostics.items())
    if (d.message.find(text) != std::string::npos) return true;
  return false;
}

// Checks that hold for any loaded motion: tracks sized and finite, all Measured, Z up, floor at 0,
// subject at the origin facing +X at frame 0.
void check_motion_invariants(const HumanMotion& m) {
  ASSERT_GT(m.num_frames, 0);
  for (Landmark l : all_landmarks()) {
    const LandmarkTrack& t = m[l];
    if (!t.present) continue;
    SCOPED_TRACE(std::string(landmark_name(l)));
    ASSERT_EQ(t.p_W.cols(), m.num_frames);
    EXPECT_TRUE(t.p_W.allFinite());
    ASSERT_EQ(t.state.size(), static_cast<std::size_t>(m.num_frames));
    EXPECT_TRUE(std::all_of(t.state.begin(), t.state.end(), [](SampleState s) { return s == SampleState::Measured; }));
  }
  EXPECT_FALSE(m.has(L::LeftHeel));
  EXPECT_FALSE(m.has(L::RightHeel));
  // Z up: head above pelvis above ankles at the first frame.
  EXPECT_GT(m[L::Head].p_W(2, 0), m[L::Pelvis].p_W(2, 0) + 0.3);
  EXPECT_GT(m[L::Pelvis].p_W(2, 0), m[L::LeftAnkle].p_W(2, 0) + 0.5);
  // Alignment: pelvis above the origin, left hip on +Y (facing +X).
  EXPECT_LT(m[L::Pelvis].p_W.col(0).head<2>().norm(), 1e-9);
  EXPECT_GT(m[L::LeftHip].p_W(1, 0), m[L::RightHip].p_W(1, 0));
  // Pelvis is the midpoint of the hips.
  EXPECT_LT((m[L::Pelvis].p_W - 0.5 * (m[L::LeftHip].p_W + m[L::RightHip].p_W)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_TRUE(m[L::Pelvis].has_orientation);
}

// Feet touch the estimated floor (z = 0): in most frames one foot landmark is within 5 cm of it,
// each foot is down in a good share of the frames, and almost nothing is far below it.
void check_floor_contact(const HumanMotion& m) {
  int any = 0, left = 0, right = 0;
  std::vector<double> lowest;
  for (int f = 0; f < m.num_frames; ++f) {
    const double zl = std::min(m[L::LeftAnkle].p_W(2, f), m[L::LeftToe].p_W(2, f));
    const double zr = std::min(m[L::RightAnkle].p_W(2, f), m[L::RightToe].p_W(2, f));
    left += zl < 0.05;
    right += zr < 0.05;
    any += std::min(zl, zr) < 0.05;
    lowest.push_back(std::min(zl, zr));
  }
  const double n = m.num_frames;
  EXPECT_GT(any / n, 0.75);
  EXPECT_GT(left / n, 0.3);
  EXPECT_GT(right / n, 0.3);
  EXPECT_GT(percentile(lowest, 0.01), -0.06);
  EXPECT_NEAR(percentile(lowest, 0.02), 0.0, 1e-9);  // the floor is the 2nd percentile (NormalizeOptions)
}

// Every .bvh in the shared folder loads without a user profile and passes the generic checks;
// the clips listed in kClips (all of them today) also match their known facts.
TEST(BvhMotion, EveryRealClipIsRecognisedAndNormalised) {
  const std::string dir = test::shared_data("bvh");
  if (dir.empty()) GTEST_SKIP() << "shared test data not found: " << test::shared_data_dir() << "/bvh";
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".bvh") files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  int known = 0;
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const std::string path = dir + "/" + file;
    const HumanMotion m = load_bvh_motion(path);
    EXPECT_EQ(m.source.path, path);
    EXPECT_EQ(m.source.format, "bvh");
    EXPECT_FALSE(m.source.units_overridden);
    EXPECT_FALSE(m.source.up_axis_overridden);
    EXPECT_EQ(m.source.up_axis, 'y');  // all shared clips are Y up in world space (README)
    EXPECT_EQ(m.source.details.at("up_axis"), "y");
    EXPECT_EQ(m.num_frames, m.source.file_frames - m.source.dropped_leading_frames);
    EXPECT_EQ(has_diagnostic(m, "synthetic T-pose"), m.source.dropped_leading_frames > 0);
    EXPECT_EQ(m.diagnostics.warning_count(), 0u);
    check_motion_invariants(m);
    check_floor_contact(m);

    const double stature = std::stod(m.source.details.at("stature_m"));
    EXPECT_GE(stature, 1.4);
    EXPECT_LE(stature, 2.0);
    // The estimate is tied to the landmarks: the head landmark is at or a little above the head joint.
    const double head_joint = std::stod(m.source.details.at("head_joint_height_m"));
    EXPECT_NEAR(stature, head_joint / 0.87, 0.01);
    // (The head joint height is the source's; levelling a tilted floor shears heights by
    // tan(tilt) times the distance from the floor fit's centre: up to ~2 cm at 0.5 deg.)
    EXPECT_LT(m.source.floor_tilt_deg, 1.0);  // no shared clip is tilted more (a larger tilt warns)
    const double shear = m.source.floor_tilt_deg > 0 ? 0.025 : 0.0;
    EXPECT_GE(m[L::Head].p_W(2, 0), head_joint - 1e-3 - shear);
    EXPECT_LE(m[L::Head].p_W(2, 0), head_joint + 0.15 + shear);

    const auto c = std::find_if(kClips.begin(), kClips.end(), [&](const ClipFacts& k) { return file == k.file; });
    if (c == kClips.end()) continue;
    ++known;
    EXPECT_EQ(m.source.profile, c->profile);
    EXPECT_EQ(m.source.units, c->units);
    EXPECT_NEAR(m.fps, c->fps, 0.01);
    EXPECT_NEAR(m.source.file_fps, c->fps, 0.01);
    EXPECT_EQ(m.source.file_frames, c->file_frames);
    EXPECT_EQ(m.source.dropped_leading_frames, c->dropped);
    for (Landmark l : all_landmarks()) {
      const bool expected = l != L::LeftHeel && l != L::RightHeel && !c->absent.count(l);
      EXPECT_EQ(m.has(l), expected) << landmark_name(l);
    }
  }
  EXPECT_EQ(known, static_cast<int>(kClips.size())) << "some clips of kClips are missing from " << dir;
}

TEST(BvhMotion, OverridesUnitsRateUpAxisAndTpose) {
  const std::string path = test::shared_data("bvh/cmu_daz_salsa_10.bvh");
  if (path.empty()) GTEST_SKIP() << "shared test data not found";
  MotionLoadOptions o;
  o.source_fps = 60;  // the CMU Daz salsa clip claims 120 Hz but is 60 Hz
  o.drop_tpose = false;
  const HumanMotion m = load_bvh_motion(path, o);
  EXPECT_DOUBLE_EQ(m.fps, 60);
  EXPECT_NEAR(m.source.file_fps, 120, 0.01);
  EXPECT_EQ(m.num_frames, 1198);
  EXPECT_EQ(m.source.dropped_leading_frames, 0);
  EXPECT_TRUE(has_diagnostic(m, "kept 1 synthetic T-pose frame"));
  EXPECT_NEAR(m.duration_s(), 1197 / 60.0, 1e-9);

  MotionLoadOptions inch;
  inch.source_units = "inch";
  const HumanMotion big = load_bvh_motion(path, inch);
  EXPECT_TRUE(big.source.units_overridden);
  EXPECT_EQ(big.source.units, "inch");
  const HumanMotion normal = load_bvh_motion(path);
  EXPECT_NEAR(std::stod(big.source.details.at("stature_m")) / std::stod(normal.source.details.at("stature_m")), 2.54, 0.01);
  EXPECT_TRUE(has_diagnostic(big, "implausible stature"));

  MotionLoadOptions wrong_up;
  wrong_up.up_axis = "z";
  const HumanMotion lying = load_bvh_motion(path, wrong_up);
  EXPECT_TRUE(lying.source.up_axis_overridden);
  EXPECT_EQ(lying.source.up_axis, 'z');
  EXPECT_TRUE(has_diagnostic(lying, "implausible stature"));
}

TEST(BvhMotion, SyntheticHumanoidInCentimetresWithTposeLeadIn) {
  test::HumanoidClip c;
  c.tpose_frames = 1;
  Diagnostics d;
  const BvhFile f = parse_bvh(test::make_humanoid_bvh(c), "humanoid.bvh", &d);
  const HumanMotion m = bvh_to_human_motion(f);
  EXPECT_EQ(m.source.profile, "mixamo");
  EXPECT_EQ(m.source.units, "cm");
  EXPECT_EQ(m.source.up_axis, 'y');
  EXPECT_EQ(m.source.dropped_leading_frames, 1);
  EXPECT_EQ(m.num_frames, 60);
  EXPECT_NEAR(m.fps, 30, 1e-6);  // Frame Time written with 10 digits
  check_motion_invariants(m);
  // Exact geometry: head joint 153 cm above the floor (the toe joints), head landmark halfway to
  // the End Site (9 cm higher), stature 1.53 / 0.87.
  EXPECT_NEAR(std::stod(m.source.details.at("head_joint_height_m")), 1.53, 1e-9);
  EXPECT_NEAR(m[L::Head].p_W(2, 0), 1.62, 1e-9);
  EXPECT_NEAR(std::stod(m.source.details.at("stature_m")), 1.53 / 0.87, 1e-3);
  EXPECT_NEAR(m[L::LeftToe].p_W(2, 0), 0.0, 1e-9);
  // Arms are down after the dropped T-pose; at file frame 30 (kept frame 29) the forearms are
  // straight: wrists 28 + 25 cm from the shoulders, 80 deg below horizontal.
  const int k = 29;
  EXPECT_NEAR(m[L::LeftShoulder].p_W(2, k) - m[L::LeftWrist].p_W(2, k), 0.53 * std::sin(80 * M_PI / 180), 1e-9);
  EXPECT_NEAR(m[L::RightShoulder].p_W(2, k) - m[L::RightWrist].p_W(2, k), 0.53 * std::sin(80 * M_PI / 180), 1e-9);
  // Landmark choice: toe = ToeBase joint (7 cm below and 13 cm ahead of the ankle), hand =
  // HandMiddle1 (10 cm beyond the wrist), chest = Spine2, neck = Neck (14 cm above Spine2).
  EXPECT_NEAR(m[L::LeftAnkle].p_W(2, 0) - m[L::LeftToe].p_W(2, 0), 0.07, 1e-9);
  EXPECT_NEAR(m[L::LeftToe].p_W(0, 0) - m[L::LeftAnkle].p_W(0, 0), 0.13, 1e-9);  // facing +X after alignment
  EXPECT_NEAR((m[L::LeftHand].p_W.col(0) - m[L::LeftWrist].p_W.col(0)).norm(), 0.10, 1e-9);
  EXPECT_NEAR((m[L::Neck].p_W.col(0) - m[L::Chest].p_W.col(0)).norm(), 0.14, 1e-9);
  EXPECT_NEAR(m[L::LeftHip].p_W(1, 0) - m[L::RightHip].p_W(1, 0), 0.18, 1e-9);

  // Kept when asked.
  MotionLoadOptions keep;
  keep.drop_tpose = false;
  EXPECT_EQ(bvh_to_human_motion(f, keep).num_frames, 61);
}

TEST(BvhMotion, TposeHoldsOfSeveralFramesAndStaticTposeClips) {
  test::HumanoidClip c;
  c.tpose_frames = 3;
  HumanMotion m = bvh_to_human_motion(parse_bvh(test::make_humanoid_bvh(c), "hold.bvh"));
  EXPECT_EQ(m.source.dropped_leading_frames, 3);
  EXPECT_EQ(m.num_frames, 60);
  // A clip that is a T-pose throughout has no jump: nothing is dropped.
  c.tpose_frames = 20;
  c.frames = 0;
  m = bvh_to_human_motion(parse_bvh(test::make_humanoid_bvh(c), "static.bvh"));
  EXPECT_EQ(m.source.dropped_leading_frames, 0);
  EXPECT_EQ(m.num_frames, 20);
  // A lead-in longer than the search window (10 frames) is not treated as synthetic.
  c.tpose_frames = 12;
  c.frames = 30;
  m = bvh_to_human_motion(parse_bvh(test::make_humanoid_bvh(c), "long.bvh"));
  EXPECT_EQ(m.source.dropped_leading_frames, 0);
}

TEST(BvhMotion, SyntheticHumanoidDetectsMetresInchesAndZUp) {
  struct Case {
    double metres_per_unit;
    char up;
    const char* units;
  };
  for (const Case& k : {Case{1.0, 'z', "m"}, Case{0.0254, 'y', "inch"}, Case{0.001, 'z', "mm"}, Case{0.0254 / 0.45, 'y', "cmu"}}) {
    SCOPED_TRACE(k.units);
    test::HumanoidClip c;
    c.metres_per_unit = k.metres_per_unit;
    c.up = k.up;
    c.prefix = "mixamorig:";
    const HumanMotion m = bvh_to_human_motion(parse_bvh(test::make_humanoid_bvh(c), "h.bvh"));
    EXPECT_EQ(m.source.units, k.units);
    EXPECT_EQ(m.source.up_axis, k.up);
    EXPECT_EQ(m.source.dropped_leading_frames, 0);
    EXPECT_EQ(m.num_frames, 60);
    EXPECT_NEAR(std::stod(m.source.details.at("stature_m")), 1.53 / 0.87, 1e-3);
    check_motion_invariants(m);
  }
}

TEST(BvhMotion, AFrameTimeRoundedFromAWholeRateIsReadAsThatRate) {
  test::HumanoidClip c;
  c.frames = 3;
  const std::string text = test::make_humanoid_bvh(c);
  auto rate = [&](const std::string& frame_time, std::string* notes = nullptr) {
    std::string t = text;
    const auto ft = t.find("Frame Time: ");
    t.replace(ft, t.find('\n', ft) - ft, "Frame Time: " + frame_time);
    const HumanMotion m = bvh_to_human_motion(parse_bvh(t, "rate.bvh"));
    if (notes)
      for (const Diagnostic& n : m.diagnostics.items()) *notes += n.message + "\n";
    return m.fps;
  };
  std::string notes;
  EXPECT_DOUBLE_EQ(rate("0.033333", &notes), 30);  // LAFAN1, Bandai: 30.0003 Hz as written
  EXPECT_NE(notes.find("read as 1/30 s (30 Hz)"), std::string::npos) << notes;
  EXPECT_DOUBLE_EQ(rate("0.008333"), 120);         // CMU, PyMO
  EXPECT_DOUBLE_EQ(rate("0.0083333"), 120);
  EXPECT_DOUBLE_EQ(rate("0.016667"), 60);          // rounded up
  EXPECT_DOUBLE_EQ(rate("0.01"), 100);             // exact already
  // Not a whole rate to the written precision, or no decimals to judge by: as written.
  EXPECT_NEAR(rate("0.033367"), 29.9697, 1e-4);   // NTSC 29.97 Hz
  EXPECT_NEAR(rate("3.3333e-02"), 30.0003, 1e-4);
  EXPECT_NEAR(rate("0.0333333333333"), 30, 1e-9);  // within 1e-13 of 1/30: 30 Hz either way
}

TEST(BvhMotion, NumericallyUnusableClipsAreLocatedErrors) {
  test::HumanoidClip c;
  c.frames = 3;
  std::string text = test::make_humanoid_bvh(c);
  // Frame Time 0 gives no rate unless --source-fps is given.
  {
    std::string t = text;
    const auto ft = t.find("Frame Time: ");
    t.replace(ft, t.find('\n', ft) - ft, "Frame Time: 0");
    const BvhFile f = parse_bvh(t, "zero_rate.bvh");
    try {
      bvh_to_human_motion(f);
      ADD_FAILURE();
    } catch (const InputError& e) {
      EXPECT_EQ(e.location(), "zero_rate.bvh:" + std::to_string(f.frame_time_line));
      EXPECT_NE(e.message().find("--source-fps"), std::string::npos);
    }
    MotionLoadOptions o;
    o.source_fps = 50;
    EXPECT_DOUBLE_EQ(bvh_to_human_motion(f, o).fps, 50);
  }
  // Finite values whose forward kinematics overflows.
  {
    // Root Xposition 1e308 in frame 0 (the row starts with "0 ") and a hip OFFSET of 1e308 (the
    // file is in cm): the hip's global x overflows to inf.
    std::string t = text;
    const auto row = t.find('\n', t.find("Frame Time:")) + 1;
    ASSERT_EQ(t.compare(row, 2, "0 "), 0);
    t.replace(row, 1, "1e308");
    t.replace(t.find("OFFSET 9 -6 0"), 13, "OFFSET 1e308 -6 0");
    const BvhFile f = parse_bvh(t, "huge.bvh");
    try {
      bvh_to_human_motion(f);
      ADD_FAILURE();
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().rfind("huge.bvh frame 0 joint ", 0), 0u) << e.what();
      EXPECT_NE(e.message().find("non-finite"), std::string::npos);
    }
  }
  // Finite but absurd coordinates (1e10 cm = 1e8 m from the origin in frame 2).
  {
    std::string t = text;
    auto row = t.find('\n', t.find("Frame Time:")) + 1;
    row = t.find('\n', row) + 1;
    row = t.find('\n', row) + 1;
    ASSERT_EQ(t.compare(row, 2, "0 "), 0);
    t.replace(row, 1, "1e10");
    try {
      bvh_to_human_motion(parse_bvh(t, "far.bvh"));
      ADD_FAILURE();
    } catch (const InputError& e) {
      EXPECT_EQ(e.location(), "far.bvh frame 2 joint LeftUpLeg") << e.what();
      EXPECT_NE(e.message().find("out of range"), std::string::npos) << e.what();
    }
  }
  // No frames.
  {
    std::string t = text;
    t.replace(t.find("Frames: 3"), 9, "Frames: 0");
    try {
      bvh_to_human_motion(parse_bvh(t, "empty.bvh"));
      ADD_FAILURE();
    } catch (const InputError& e) {
      EXPECT_NE(e.message().find("no frames"), std::string::npos);
    }
  }
  MotionLoadOptions bad_fps;
  bad_fps.source_fps = -1;
  EXPECT_THROW(bvh_to_human_motion(parse_bvh(text, "x.bvh"), bad_fps), InputError);
  MotionLoadOptions bad_units;
  bad_units.source_units = "furlong";
  EXPECT_THROW(bvh_to_human_motion(parse_bvh(text, "x.bvh"), bad_units), InputError);
}

TEST(BvhMotion, LoadReportsReaderWarningsFirst) {
  test::HumanoidClip c;
  std::string text = test::make_humanoid_bvh(c);
  text.replace(text.find("Frames: 60"), 10, "Frames: 59");
  const std::string path = test::scratch_dir() + "/extra.bvh";
  std::ofstream(path) << text;
  const HumanMotion m = load_bvh_motion(path);
  EXPECT_EQ(m.num_frames, 59);
  ASSERT_FALSE(m.diagnostics.empty());
  EXPECT_EQ(m.diagnostics.items()[0].severity, Diagnostic::Severity::Warning);
  EXPECT_NE(m.diagnostics.items()[0].message.find("ignored"), std::string::npos);
}

}  // namespace
}  // namespace rt
