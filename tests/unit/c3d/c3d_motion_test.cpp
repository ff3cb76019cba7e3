// C3D -> HumanMotion: marker-set profiles on the shared real files, joint-centre accuracy against
// Vicon's own Plug-in Gait outputs, gaps and trimming on a synthetic walker, overrides, marker maps.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "c3d_test_writer.hpp"
#include "formats/c3d/c3d_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/c3d/c3d_motion.hpp"
#include "retarget/motion/c3d/marker_trajectories.hpp"
#include "support/test_paths.hpp"
#include "synthetic_walker.hpp"

namespace rt {
namespace {

MotionLoadOptions raw_options() {
  MotionLoadOptions o;
  o.normalize.align_start = false;
  o.normalize.move_floor_to_zero = false;
  return o;
}

HumanMotion from_spec(const test::C3dSpec& spec, const MotionLoadOptions& options = raw_options(),
                      const std::string& name = "walker.c3d") {
  const std::string bytes = test::write_c3d(spec).bytes;
  Diagnostics reader;
  const c3d::C3dFile f = c3d::parse_c3d(bytes, name, &reader);
  return c3d_to_motion(f, options, reader);
}

std::string all_diagnostics(const HumanMotion& m) {
  std::string s;
  for (const auto& d : m.diagnostics.items()) s += d.to_string() + "\n";
  return s;
}

double median_length(const HumanMotion& m, Landmark a, Landmark b) {
  std::vector<double> v;
  for (int f = 0; f < m.num_frames; ++f)
    if (m[a].valid(f) && m[b].valid(f)) v.push_back((m[a].p_W.col(f) - m[b].p_W.col(f)).norm());
  if (v.empty()) return -1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

std::vector<Landmark> except(std::initializer_list<Landmark> absent) {
  std::vector<Landmark> out;
  for (Landmark l : all_landmarks())
    if (std::find(absent.begin(), absent.end(), l) == absent.end()) out.push_back(l);
  return out;
}

const std::vector<Landmark> kArms = {Landmark::LeftShoulder, Landmark::LeftElbow,  Landmark::LeftWrist,
                                     Landmark::LeftHand,     Landmark::RightShoulder, Landmark::RightElbow,
                                     Landmark::RightWrist,   Landmark::RightHand};

struct WholeBody {
  const char* file;
  const char* profile;
  std::vector<Landmark> expected;  // every landmark that must be present
  int frames;                      // frames kept after trimming
};

std::vector<WholeBody> whole_body_files() {
  std::vector<Landmark> no_arms = except({Landmark::LeftShoulder, Landmark::LeftElbow, Landmark::LeftWrist,
                                          Landmark::LeftHand, Landmark::RightShoulder, Landmark::RightElbow,
                                          Landmark::RightWrist, Landmark::RightHand});
  return {
      {"c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d", "plug-in-gait", except({}), 255},
      {"c3d/ezc3d_Qualisys_fullbody_forceplates.c3d", "cast", except({}), 340},
      {"c3d/btk_mocap36_optitrack_fullbody.c3d", "optitrack-skeleton", except({Landmark::LeftHeel, Landmark::RightHeel}), 1151},
      {"c3d/opensim_walking2_gait_forceplates.c3d", "plug-in-gait", no_arms, 554},
  };
}

TEST(C3dMotion, WholeBodyFilesAreRecognisedAndPlausible) {
  int found = 0;
  for (const WholeBody& w : whole_body_files()) {
    const std::string path = test::shared_data(w.file);
    if (path.empty()) continue;
    ++found;
    SCOPED_TRACE(w.file);
    const HumanMotion m = load_c3d_motion(path, MotionLoadOptions{});
    EXPECT_EQ(m.source.format, "c3d");
    EXPECT_EQ(m.source.profile, w.profile);
    EXPECT_EQ(m.source.units, "mm");
    EXPECT_EQ(m.source.up_axis, 'z');
    EXPECT_EQ(m.num_frames, w.frames);
    for (Landmark l : all_landmarks()) {
      const bool expected = std::find(w.expected.begin(), w.expected.end(), l) != w.expected.end();
      EXPECT_EQ(m.has(l), expected) << landmark_name(l);
    }
    // Segment lengths in human ranges [m].
    for (auto [a, b, lo, hi] : {std::tuple{Landmark::LeftHip, Landmark::LeftKnee, 0.33, 0.52},
                                std::tuple{Landmark::RightHip, Landmark::RightKnee, 0.33, 0.52},
                                std::tuple{Landmark::LeftKnee, Landmark::LeftAnkle, 0.30, 0.50},
                                std::tuple{Landmark::RightKnee, Landmark::RightAnkle, 0.30, 0.50},
                                std::tuple{Landmark::LeftHip, Landmark::RightHip, 0.12, 0.24},
                                std::tuple{Landmark::LeftShoulder, Landmark::LeftElbow, 0.22, 0.40},
                                std::tuple{Landmark::RightShoulder, Landmark::RightElbow, 0.22, 0.40},
                                std::tuple{Landmark::LeftElbow, Landmark::LeftWrist, 0.18, 0.33},
                                std::tuple{Landmark::RightElbow, Landmark::RightWrist, 0.18, 0.33}}) {
      if (!m.has(a) || !m.has(b)) continue;
      const double len = median_length(m, a, b);
      EXPECT_GT(len, lo) << landmark_name(a) << "-" << landmark_name(b);
      EXPECT_LT(len, hi) << landmark_name(a) << "-" << landmark_name(b);
    }
    // Stature from the first frame: head centre (about 0.1 m below the vertex) above the floor.
    ASSERT_TRUE(m[Landmark::Head].valid(0));
    const double stature = m[Landmark::Head].p_W(2, 0) + 0.10;
    EXPECT_GT(stature, 1.4);
    EXPECT_LT(stature, 2.0);
    // Upright: head above neck above pelvis above knees above ankles.
    const int f0 = 0;
    EXPECT_GT(m[Landmark::Head].p_W(2, f0), m[Landmark::Neck].p_W(2, f0));
    EXPECT_GT(m[Landmark::Neck].p_W(2, f0), m[Landmark::Pelvis].p_W(2, f0));
    EXPECT_GT(m[Landmark::Pelvis].p_W(2, f0), m[Landmark::LeftKnee].p_W(2, f0));
    EXPECT_GT(m[Landmark::LeftKnee].p_W(2, f0), m[Landmark::LeftAnkle].p_W(2, f0));
    // Both feet reach the estimated floor (z = 0) during the trial, and never sink far below it.
    for (auto side : {std::array{Landmark::LeftAnkle, Landmark::LeftToe, Landmark::LeftHeel},
                      std::array{Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel}}) {
      double lowest = INFINITY, deepest = INFINITY;
      for (int f = 0; f < m.num_frames; ++f) {
        double z = INFINITY;
        for (Landmark l : side)
          if (m.has(l) && m[l].valid(f)) z = std::min(z, m[l].p_W(2, f));
        lowest = std::min(lowest, z);
        deepest = std::min(deepest, z);
      }
      EXPECT_LT(lowest, 0.03) << landmark_name(side[0]);
      EXPECT_GT(deepest, -0.03) << landmark_name(side[0]);
    }
    // Normalised: pelvis above the origin facing +X at frame 0, orientations derived.
    EXPECT_NEAR(m[Landmark::Pelvis].p_W(0, 0), 0, 1e-9);
    EXPECT_NEAR(m[Landmark::Pelvis].p_W(1, 0), 0, 1e-9);
    EXPECT_TRUE(m[Landmark::Pelvis].has_orientation);
    EXPECT_GT(m[Landmark::LeftHip].p_W(1, 0), m[Landmark::RightHip].p_W(1, 0));
  }
  if (found == 0) GTEST_SKIP() << "shared C3D data not found";
}

TEST(C3dMotion, PluginGaitJointCentresMatchViconOutputs) {
  RT_REQUIRE_SHARED(path, "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d");
  const HumanMotion m = load_c3d_motion(path, raw_options());
  const c3d::C3dFile f = c3d::read_c3d(path);
  ASSERT_EQ(m.num_frames, f.points.num_frames);  // nothing trimmed
  auto point = [&](const std::string& label) {
    const auto it = std::find(f.point_labels.begin(), f.point_labels.end(), label);
    EXPECT_NE(it, f.point_labels.end()) << label;
    return static_cast<int>(it - f.point_labels.begin());
  };
  // Plug-in Gait's segment origins/proximal points: FEP = hip, FEO = knee, TIO = ankle,
  // CLO = shoulder, HUO = elbow, RAO = wrist centre.
  struct Check {
    Landmark l;
    const char* vicon;
    double median_mm, max_mm;
  };
  for (const Check& c : {Check{Landmark::LeftHip, "LFEP", 3, 3}, Check{Landmark::RightHip, "RFEP", 3, 3},
                         Check{Landmark::LeftKnee, "LFEO", 3, 3}, Check{Landmark::RightKnee, "RFEO", 3, 3},
                         Check{Landmark::LeftAnkle, "LTIO", 3, 3}, Check{Landmark::RightAnkle, "RTIO", 3, 3},
                         Check{Landmark::Pelvis, "PELO", 3, 3}, Check{Landmark::LeftShoulder, "LCLO", 12, 15},
                         Check{Landmark::RightShoulder, "RCLO", 12, 15}, Check{Landmark::LeftElbow, "LHUO", 6, 8},
                         Check{Landmark::RightElbow, "RHUO", 6, 8}, Check{Landmark::LeftWrist, "LRAO", 8, 10},
                         Check{Landmark::RightWrist, "RRAO", 8, 10}}) {
    const int p = point(c.vicon);
    std::vector<double> err;
    for (int k = 0; k < m.num_frames; ++k) {
      if (!f.points.valid(k, p)) continue;
      ASSERT_TRUE(m[c.l].valid(k));
      const float* q = f.points.at(k, p);
      err.push_back(1000 * (m[c.l].p_W.col(k) - 0.001 * Vec3(q[0], q[1], q[2])).norm());
    }
    ASSERT_GT(err.size(), 200u);
    std::sort(err.begin(), err.end());
    EXPECT_LT(err[err.size() / 2], c.median_mm) << landmark_name(c.l);
    EXPECT_LT(err.back(), c.max_mm) << landmark_name(c.l);
  }
  // The Davis regression was chosen because the file carries the subject's leg length.
  EXPECT_NE(all_diagnostics(m).find("left_hip: Davis 1991"), std::string::npos);
}

TEST(C3dMotion, Eb015LowerBodyClusters) {
  RT_REQUIRE_SHARED(intel, "c3d/c3dorg_sample01_Eb015pi_intel_int.c3d");
  RT_REQUIRE_SHARED(dec, "c3d/c3dorg_sample01_Eb015vr_dec_real.c3d");
  RT_REQUIRE_SHARED(sgi, "c3d/c3dorg_sample01_Eb015si_sgi_int.c3d");
  const HumanMotion a = load_c3d_motion(intel, raw_options());
  EXPECT_EQ(a.source.profile, "segment-clusters");
  for (Landmark l : {Landmark::Pelvis, Landmark::LeftHip, Landmark::RightHip, Landmark::LeftKnee, Landmark::RightKnee,
                     Landmark::RightAnkle, Landmark::RightToe})
    EXPECT_TRUE(a.has(l)) << landmark_name(l);
  for (Landmark l : {Landmark::Head, Landmark::Neck, Landmark::LeftShoulder, Landmark::RightWrist})
    EXPECT_FALSE(a.has(l)) << landmark_name(l);
  const std::string diag = all_diagnostics(a);
  EXPECT_NE(diag.find("landmarks not available from the segment-clusters markers: spine, chest, neck, head"),
            std::string::npos)
      << diag;
  // The left foot cluster is not rigid (marker distances vary 20-83 mm): no left ankle, and said so.
  EXPECT_FALSE(a.has(Landmark::LeftAnkle));
  EXPECT_NE(diag.find("cluster LFT1"), std::string::npos) << diag;
  EXPECT_GT(median_length(a, Landmark::LeftHip, Landmark::LeftKnee), 0.33);
  EXPECT_LT(median_length(a, Landmark::LeftHip, Landmark::LeftKnee), 0.45);
  EXPECT_GT(median_length(a, Landmark::RightKnee, Landmark::RightAnkle), 0.30);
  EXPECT_LT(median_length(a, Landmark::RightKnee, Landmark::RightAnkle), 0.45);
  // The three processor formats give the same landmarks.
  for (const std::string& other : {dec, sgi}) {
    const HumanMotion b = load_c3d_motion(other, raw_options());
    ASSERT_EQ(b.num_frames, a.num_frames);
    for (Landmark l : all_landmarks()) {
      ASSERT_EQ(a.has(l), b.has(l));
      if (!a.has(l)) continue;
      EXPECT_LT((a[l].p_W - b[l].p_W).cwiseAbs().maxCoeff(), 0.001) << landmark_name(l);
    }
  }
}

TEST(C3dMotion, TrimsFramesWithoutTheSubject) {
  RT_REQUIRE_SHARED(walking, "c3d/opensim_walking2_gait_forceplates.c3d");
  const HumanMotion w = load_c3d_motion(walking, MotionLoadOptions{});
  EXPECT_GT(std::stoi(w.source.details.at("trimmed_leading_frames")), 300);
  EXPECT_GT(std::stoi(w.source.details.at("trimmed_trailing_frames")), 300);
  EXPECT_EQ(w.source.file_frames, 1249);
  EXPECT_NE(all_diagnostics(w).find("kept frames 377-930 of 1-1249"), std::string::npos) << all_diagnostics(w);
  // The virtual joint-centre markers are used, extended beyond their own span from the clusters.
  EXPECT_NE(all_diagnostics(w).find("left_knee: virtual joint-centre marker LKJC"), std::string::npos);
  EXPECT_GT(std::stoi(w.source.details.at("rigid_filled_samples")), 1000);

  RT_REQUIRE_SHARED(opti, "c3d/btk_mocap36_optitrack_fullbody.c3d");
  const HumanMotion o = load_c3d_motion(opti, MotionLoadOptions{});
  EXPECT_EQ(o.source.details.at("trimmed_leading_frames"), "0");
  EXPECT_EQ(o.source.details.at("trimmed_trailing_frames"), "229");
}

TEST(C3dMotion, SourceDetails) {
  RT_REQUIRE_SHARED(path, "c3d/ezc3d_Qualisys_fullbody_forceplates.c3d");
  const HumanMotion m = load_c3d_motion(path, MotionLoadOptions{});
  EXPECT_DOUBLE_EQ(m.fps, 200);
  EXPECT_DOUBLE_EQ(m.source.file_fps, 200);
  EXPECT_EQ(m.source.file_frames, 340);
  const auto& d = m.source.details;
  EXPECT_EQ(d.at("markers"), "55");
  EXPECT_EQ(d.at("analog_channels"), "69");
  EXPECT_EQ(d.at("first_frame"), "705");
  EXPECT_EQ(d.at("events"), "7");
  EXPECT_EQ(d.at("processor"), "Intel");
  // QTM writes POINT:Y_SCREEN '-Z' although the data are Z up: the data win, with a note.
  EXPECT_NE(all_diagnostics(m).find("[POINT:Y_SCREEN]: note: says '-Z'"), std::string::npos) << all_diagnostics(m);
}

TEST(C3dMotion, UnlabeledFileNeedsAMarkerMap) {
  RT_REQUIRE_SHARED(path, "c3d/c3dorg_sample20_phasespace_noparams.c3d");
  try {
    load_c3d_motion(path, MotionLoadOptions{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos);
    EXPECT_NE(m.find("@0x0200 [POINT:LABELS]: cannot recognise the marker set: 40 markers, none labelled"), std::string::npos) << m;
    EXPECT_NE(m.find("missing landmarks: pelvis, spine, chest"), std::string::npos) << m;
    EXPECT_NE(m.find("--marker-map FILE.yaml"), std::string::npos) << m;
  }
}

// ---- synthetic walker: gaps, trimming, overrides ---------------------------------------------------

TEST(C3dMotion, GapsAreInterpolatedOrReported) {
  const test::Walker w;
  // LKNE: 6 missing frames (0.06 s, interpolated). LTOE: 50 frames (0.5 s, left Missing).
  // LANK: 30 frames (0.3 s): the left ankle centre needs it, so the ankle has a long gap.
  // LASI: 40 frames, rebuilt from the other three pelvis markers (rigid cluster).
  const test::C3dSpec spec = w.spec([](const std::string& n, int f) {
    return (n == "LKNE" && f >= 60 && f < 66) || (n == "LTOE" && f >= 100 && f < 150) ||
           (n == "LANK" && f >= 200 && f < 230) || (n == "LASI" && f >= 250 && f < 290);
  });
  const HumanMotion m = from_spec(spec);
  const std::string diag = all_diagnostics(m);
  EXPECT_EQ(m.source.profile, "plug-in-gait");  // "Matt:" prefixes stripped
  EXPECT_EQ(m.num_frames, w.frames - w.absent_leading);
  EXPECT_NE(diag.find("kept frames 21-300 of 1-300"), std::string::npos) << diag;
  const int k0 = w.absent_leading;  // file frame index of motion frame 0
  auto truth_m = [](const Vec3& mm) { return Vec3(0.001 * mm); };

  // Short knee gap: interpolated, close to the truth.
  const LandmarkTrack& knee = m[Landmark::LeftKnee];
  for (int f = 60; f < 66; ++f) {
    EXPECT_EQ(knee.state[static_cast<std::size_t>(f - k0)], SampleState::Interpolated);
    EXPECT_LT((knee.p_W.col(f - k0) - truth_m(w.knee(f, 0))).norm(), 0.002);
  }
  EXPECT_EQ(knee.state[static_cast<std::size_t>(59 - k0)], SampleState::Measured);
  EXPECT_LT((knee.p_W.col(70 - k0) - truth_m(w.knee(70, 0))).norm(), 1e-4);

  // Long toe gap: Missing, holding the nearest valid position, reported with file frame numbers.
  const LandmarkTrack& toe = m[Landmark::LeftToe];
  for (int f = 100; f < 150; ++f) EXPECT_EQ(toe.state[static_cast<std::size_t>(f - k0)], SampleState::Missing);
  EXPECT_EQ(toe.p_W.col(101 - k0), toe.p_W.col(99 - k0));
  EXPECT_EQ(toe.p_W.col(148 - k0), toe.p_W.col(150 - k0));
  EXPECT_NE(diag.find("left_toe: missing in file frames 101-150"), std::string::npos) << diag;
  EXPECT_NE(diag.find("left_ankle: missing in file frames 201-230"), std::string::npos) << diag;
  EXPECT_EQ(m.source.details.at("missing_gaps"), "2");

  // LASI gap: rebuilt exactly from the rigid pelvis, so the hips stay valid (as Interpolated).
  const LandmarkTrack& hip = m[Landmark::LeftHip];
  for (int f = 250; f < 290; f += 7) {
    EXPECT_EQ(hip.state[static_cast<std::size_t>(f - k0)], SampleState::Interpolated);
    EXPECT_LT((hip.p_W.col(f - k0) - truth_m(w.hip(f, 0))).norm(), 1e-4);
  }
  EXPECT_EQ(m.source.details.at("rigid_filled_samples"), "40");
  // Harrington hip centres and the other joint centres where nothing is missing.
  EXPECT_LT((m[Landmark::RightHip].p_W.col(30) - truth_m(w.hip(30 + k0, 1))).norm(), 1e-4);
  EXPECT_LT((m[Landmark::RightAnkle].p_W.col(30) - truth_m(w.ankle(30 + k0, 1))).norm(), 1e-4);
  EXPECT_NE(diag.find("Harrington 2007"), std::string::npos);
}

TEST(C3dMotion, MaxGapOptionControlsInterpolation) {
  const test::Walker w;
  const test::C3dSpec spec = w.spec([](const std::string& n, int f) { return n == "LTOE" && f >= 100 && f < 150; });
  MotionLoadOptions o = raw_options();
  o.max_gap_s = 0.6;
  const HumanMotion m = from_spec(spec, o);
  EXPECT_EQ(m[Landmark::LeftToe].state[static_cast<std::size_t>(120 - w.absent_leading)], SampleState::Interpolated);
  EXPECT_EQ(m.source.details.at("interpolated_gaps"), "1");
  o.max_gap_s = -1;
  EXPECT_THROW(from_spec(spec, o), InputError);
}

TEST(C3dMotion, UnitsRateAndUpAxisOverrides) {
  const test::Walker w;
  test::C3dSpec spec = w.spec();
  MotionLoadOptions o = raw_options();
  o.source_units = "cm";
  o.source_fps = 50;
  const HumanMotion m = from_spec(spec, o);
  EXPECT_TRUE(m.source.units_overridden);
  EXPECT_EQ(m.source.units, "cm");
  EXPECT_DOUBLE_EQ(m.fps, 50);
  EXPECT_DOUBLE_EQ(m.source.file_fps, 100);
  EXPECT_LT((m[Landmark::LeftKnee].p_W.col(0) - 0.01 * w.knee(w.absent_leading, 0)).norm(), 1e-6);

  // The same walker stored Y up: detected, and rotated back to Z up.
  for (auto& row : spec.samples)
    for (auto& s : row) s = {s[0], s[2], -s[1], s[3]};
  spec.units = "m";  // and in metres per POINT:UNITS
  for (auto& row : spec.samples)
    for (auto& s : row) s = {s[0] / 1000, s[1] / 1000, s[2] / 1000, s[3]};
  const HumanMotion y = from_spec(spec, MotionLoadOptions{});
  EXPECT_EQ(y.source.up_axis, 'y');
  EXPECT_EQ(y.source.units, "m");
  EXPECT_GT(y[Landmark::Head].p_W(2, 0), 1.5);
  EXPECT_NEAR(y.source.floor_height_m, 0.04, 1e-6);
  // Forcing the wrong axis is obeyed (and produces a lying subject).
  MotionLoadOptions forced;
  forced.up_axis = "z";
  const HumanMotion z = from_spec(spec, forced);
  EXPECT_TRUE(z.source.up_axis_overridden);
  EXPECT_LT(z[Landmark::Head].p_W(2, 0), 0.5);
}

// Issue 18 item 3: a rate or a duration beyond the limits (core/limits.hpp) is a located error
// before anything is sized from it (POINT:RATE 0.001 made a 3600-frame walker last an hour+).
TEST(C3dMotion, RateAndDurationBounds) {
  const test::Walker w;
  for (const double rate : {0.001, 1e-30, 2e4}) {
    test::C3dSpec spec = w.spec();
    spec.rate = rate;
    try {
      from_spec(spec);
      ADD_FAILURE() << "no error for POINT:RATE " << rate;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("[POINT:RATE]"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not between 1 and 10000 Hz"), std::string::npos) << e.what();
    }
  }
  MotionLoadOptions o = raw_options();
  for (const double fps : {1e-6, 0.5, 1e6}) {
    o.source_fps = fps;
    EXPECT_THROW(from_spec(w.spec(), o), InputError) << fps;
  }
  // 300 frames at 1 Hz is 5 minutes: fine; the limit is the duration, not the rate alone.
  o.source_fps = 1;
  EXPECT_NO_THROW(from_spec(w.spec(), o));
}

// Issue 18 item 13: a sacrum marker named VSAC (BTK others/Gait.c3d), and units cut to 'mete'.
TEST(C3dMotion, BtkCorpusMarkerNamesAndUnits) {
  {
    RT_REQUIRE_SHARED(path, "c3d/btkdata/others_Gait_VSAC.c3d");
    const HumanMotion m = load_c3d_motion(path, MotionLoadOptions{});
    EXPECT_TRUE(m.has(Landmark::Pelvis));
  }
  {  // Elite/BTS names with spaces ('r asis', 'r met'): a lower body, not an unknown marker set
    RT_REQUIRE_SHARED(path, "c3d/btkdata/c3dorg_sample28_dynamic_elite.c3d");
    const HumanMotion m = load_c3d_motion(path, MotionLoadOptions{});
    EXPECT_TRUE(m.has(Landmark::Pelvis));
    EXPECT_TRUE(m.has(Landmark::LeftKnee));
    EXPECT_TRUE(m.has(Landmark::RightToe));  // from 'r met'
  }
  EXPECT_EQ(normalise_marker_name("Subject:r asis "), "RASIS");
  // c3d.org FP1/FP2 store 'mete' (truncated "meters"): metres, with a note, not millimetres.
  const test::Walker w;
  test::C3dSpec spec = w.spec();
  spec.units = "mete";
  for (auto& row : spec.samples)
    for (auto& smp : row) smp = {smp[0] / 1000, smp[1] / 1000, smp[2] / 1000, smp[3]};
  const HumanMotion m = from_spec(spec);
  EXPECT_EQ(m.source.units, "m");
  EXPECT_NE(all_diagnostics(m).find("'mete' read as m"), std::string::npos) << all_diagnostics(m);
}

TEST(C3dMotion, SubjectNeverFullyInView) {
  const test::Walker w;
  const test::C3dSpec spec = w.spec([](const std::string& n, int f) {
    return (n == "LKNE" && f < 150) || (n == "RKNE" && f >= 150);
  });
  try {
    from_spec(spec);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("never in view together"), std::string::npos) << e.what();
  }
}

// ---- marker maps -----------------------------------------------------------------------------

std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = test::scratch_dir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(C3dMotion, MarkerMapOverridesAndNumberedPoints) {
  const test::Walker w;
  test::C3dSpec spec = w.spec();
  // Unlabeled file: landmarks by point number only.
  for (auto& l : spec.labels) l.clear();
  std::map<std::string, int> number;  // 1-based point number of each marker
  int k = 1;
  for (const auto& [name, p] : w.markers(0)) number[name] = k++;
  auto n = [&](const char* name) { return "'#" + std::to_string(number.at(name)) + "'"; };
  const std::string yaml = "name: lab\nlandmarks:\n  pelvis: [" + n("LASI") + ", " + n("RASI") + ", " + n("LPSI") + ", " +
                           n("RPSI") + "]\n  left_ankle: [" + n("LANK") + ", " + n("LMED") + "]\n  right_ankle: [" +
                           n("RANK") + ", " + n("RMED") + "]\n  left_toe: " + n("LTOE") + "\n  head: [" + n("LFHD") +
                           ", " + n("RFHD") + "]\n";
  MotionLoadOptions o = raw_options();
  o.profile_path = write_text("map.yaml", yaml);
  const HumanMotion m = from_spec(spec, o);
  EXPECT_EQ(m.source.profile, "marker-map:lab");
  EXPECT_TRUE(m.has(Landmark::Pelvis));
  EXPECT_TRUE(m.has(Landmark::LeftToe));
  EXPECT_FALSE(m.has(Landmark::LeftKnee));
  EXPECT_LT((m[Landmark::LeftAnkle].p_W.col(5) - 0.001 * w.ankle(5 + w.absent_leading, 0)).norm(), 1e-6);

  // base: auto keeps the built-in profile and overrides one landmark.
  const test::C3dSpec labelled = w.spec();
  o.profile_path = write_text("auto.yaml", "base: auto\nlandmarks:\n  left_knee: LKNE\n");
  const HumanMotion a = from_spec(labelled, o);
  EXPECT_EQ(a.source.profile, "plug-in-gait+marker-map:auto.yaml");
  EXPECT_LT((a[Landmark::LeftKnee].p_W.col(0) - 0.001 * w.markers(w.absent_leading).at("LKNE")).norm(), 1e-6);
  EXPECT_TRUE(a.has(Landmark::RightElbow));
}

TEST(C3dMotion, BadMarkerMapsSayWhere) {
  const test::Walker w;
  const test::C3dSpec spec = w.spec();
  MotionLoadOptions o = raw_options();
  struct Case {
    const char* yaml;
    const char* expected;
  };
  for (const Case& c : {Case{"landmarks:\n  left_nee: LKNE\n", "map.yaml:2: landmarks.left_nee: unknown landmark"},
                        Case{"landmark:\n  left_knee: LKNE\n", "map.yaml:1: landmark: unknown key"},
                        Case{"landmarks:\n  pelvis: [LASI]\n  left_knee: [LKNE, NOPE]\n",
                             "map.yaml:3: landmarks.left_knee: marker 'NOPE' is not in the C3D file"},
                        Case{"base: maybe\nlandmarks:\n  pelvis: LASI\n", "map.yaml:1: base: expected 'none' or 'auto'"},
                        Case{"landmarks: [1, 2]\n", "map.yaml:1: landmarks: expected a map"},
                        Case{"landmarks:\n  pelvis: {a: 1}\n", "map.yaml:2: landmarks.pelvis: expected a string"}}) {
    o.profile_path = write_text("map.yaml", c.yaml);
    try {
      from_spec(spec, o);
      ADD_FAILURE() << "no error for " << c.yaml;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
  // A map that gives no foot cannot be normalised onto a floor.
  o.profile_path = write_text("map.yaml", "landmarks:\n  pelvis: [LASI, RASI]\n");
  EXPECT_THROW(from_spec(spec, o), InputError);
}

}  // namespace
}  // namespace rt
