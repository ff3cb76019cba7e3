// Plausibility checks of loaded clips (source_checks.hpp): stature (wrong units), repeated frames
// and a centre falling faster than gravity (a stated rate higher than the data's).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/motion/source_checks.hpp"
#include "support/motion_builder.hpp"

namespace rt {
namespace {

// A head and a wrist moving at `fps`; frame k holds sample k / (repeat + 1): every sample
// repeated `repeat` times.
HumanMotion moving(int frames, double fps, int repeat, double head_height_m = 1.5) {
  HumanMotion m;
  m.fps = fps;
  m.num_frames = frames;
  m.source.path = "clip.bvh";
  m.source.units = "cm";
  LandmarkTrack& head = test::measured_track(m, Landmark::Head);
  LandmarkTrack& wrist = test::measured_track(m, Landmark::LeftWrist);
  for (int t = 0; t < frames; ++t) {
    const double s = t / (repeat + 1);
    head.p_W.col(t) << 0.01 * s, 0, head_height_m;
    wrist.p_W.col(t) << 0.3 * std::sin(0.1 * s), 0.2, 1.0;
  }
  return m;
}

TEST(SourceChecks, StatureFromTheReaderOrTheHeadLandmark) {
  HumanMotion m = moving(20, 60, 0, 1.5);
  EXPECT_NEAR(*estimate_stature_m(m), 1.5 / 0.87, 1e-12);
  m.source.details["stature_m"] = "1.64";
  EXPECT_NEAR(*estimate_stature_m(m), 1.64, 1e-12);
  EXPECT_NO_THROW(check_stature(m));
  m.source.details["stature_m"] = "164.37";
  try {
    check_stature(m);
    ADD_FAILURE() << "164 m accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("clip.bvh: implausible stature 164 m with units cm (detected)"), std::string::npos) << what;
    EXPECT_NE(what.find("--source-units"), std::string::npos) << what;
    EXPECT_NE(what.find("--force"), std::string::npos) << what;
  }
  m.source.details["stature_m"] = "0.0164";
  m.source.units_overridden = true;
  EXPECT_THROW(check_stature(m), InputError);
  m.source.details.clear();
  m[Landmark::Head] = LandmarkTrack();  // nothing to estimate from: no check
  EXPECT_FALSE(estimate_stature_m(m));
  EXPECT_NO_THROW(check_stature(m));
}

TEST(SourceChecks, RegularRepeatsGiveTheDataRate) {
  const RepeatedFrames none = find_repeated_frames(moving(200, 120, 0));
  EXPECT_EQ(none.repeated, 0);
  EXPECT_EQ(none.run_length, 0);
  const RepeatedFrames doubled = find_repeated_frames(moving(200, 120, 1));
  EXPECT_EQ(doubled.repeated, 100);
  EXPECT_EQ(doubled.run_length, 1);
  EXPECT_DOUBLE_EQ(doubled.data_fps, 60);
  const RepeatedFrames tripled = find_repeated_frames(moving(300, 90, 2));
  EXPECT_EQ(tripled.run_length, 2);
  EXPECT_DOUBLE_EQ(tripled.data_fps, 30);
}

TEST(SourceChecks, HoldingStillIsNotARepeatPattern) {
  // Moves for 50 frames, then holds still for 150: many repeats, but one run.
  HumanMotion m = moving(200, 120, 0);
  for (Landmark l : {Landmark::Head, Landmark::LeftWrist})
    for (int t = 50; t < 200; ++t) m[l].p_W.col(t) = m[l].p_W.col(49);
  const RepeatedFrames r = find_repeated_frames(m);
  EXPECT_EQ(r.repeated, 150);
  EXPECT_EQ(r.run_length, 0);
  // Interpolated samples are not evidence of repetition.
  HumanMotion gaps = moving(200, 120, 1);
  for (auto& s : gaps[Landmark::LeftWrist].state) s = SampleState::Interpolated;
  EXPECT_EQ(find_repeated_frames(gaps).repeated, 0);
}

TEST(SourceChecks, RepeatsWithinNoiseStillCount) {
  // Every sample twice, with 0.02 mm of noise on every coordinate (a re-export, a float round
  // trip): still every 2nd frame repeats.
  HumanMotion m = moving(240, 120, 1);
  for (LandmarkTrack& l : m.landmarks)
    if (l.present)
      for (int t = 0; t < m.num_frames; ++t) l.p_W.col(t) += 2e-5 * Vec3(std::sin(7.1 * t), std::cos(3.3 * t), std::sin(1.7 * t));
  const RepeatedFrames r = find_repeated_frames(m);
  EXPECT_EQ(r.run_length, 1);
  EXPECT_DOUBLE_EQ(r.data_fps, 60);
  // Holding still with that noise: many small displacements, but no regular pattern.
  HumanMotion still = moving(240, 120, 0);
  for (LandmarkTrack& l : still.landmarks)
    if (l.present)
      for (int t = 0; t < still.num_frames; ++t)
        l.p_W.col(t) = l.p_W.col(0) + 2e-5 * Vec3(std::sin(7.1 * t), std::cos(3.3 * t), std::sin(1.7 * t));
  EXPECT_EQ(find_repeated_frames(still).run_length, 0);
}

// Three landmarks rising and falling as in a jump: ballistic flight (1 g down) for 0.6 s, then a
// stance dip, played at `speed` times its real rate (the stated rate `speed` times too high).
HumanMotion hopping(double fps, double speed) {
  HumanMotion m;
  m.fps = fps;
  m.num_frames = static_cast<int>(4 * fps / speed);
  m.source.path = "hops.bvh";
  std::vector<LandmarkTrack*> tracks = {&test::measured_track(m, Landmark::Pelvis), &test::measured_track(m, Landmark::Head),
                                        &test::measured_track(m, Landmark::LeftAnkle)};
  const double g = 9.80665, flight = 0.6, stance = 0.4;
  for (int t = 0; t < m.num_frames; ++t) {
    const double real_s = t / fps * speed;
    const double phase = std::fmod(real_s, flight + stance);
    // Flight: z = v t - g t²/2 (v = g flight / 2); stance: a smooth dip of 5 cm.
    const double z = phase < flight ? g * flight / 2 * phase - g / 2 * phase * phase
                                    : -0.05 * std::sin(M_PI * (phase - flight) / stance);
    for (std::size_t i = 0; i < tracks.size(); ++i) tracks[i]->p_W.col(t) << 0.1 * real_s, 0, 0.1 + 0.7 * i + z;
  }
  return m;
}

TEST(SourceChecks, ACentreFallingFasterThanGravityGivesTheRate) {
  const CentreFall real = find_centre_fall(hopping(120, 1));
  EXPECT_NEAR(real.peak_g, 1.0, 0.1);  // free flight
  EXPECT_EQ(real.slow_down, 0);
  const CentreFall doubled = find_centre_fall(hopping(120, 2));  // 60 Hz data stated as 120 Hz
  EXPECT_NEAR(doubled.peak_g, 4.0, 0.4);
  EXPECT_GE(doubled.span_s, kMinCentreFall_s);
  EXPECT_EQ(doubled.slow_down, 2);
  EXPECT_DOUBLE_EQ(doubled.data_fps, 60);
  EXPECT_EQ(find_centre_fall(hopping(100, 3)).slow_down, 3);

  HumanMotion m = hopping(120, 2);
  check_frame_rate_against_data(m);
  ASSERT_EQ(m.diagnostics.warning_count(), 1u);
  const std::string what = m.diagnostics.items().front().to_string();
  EXPECT_NE(what.find("hops.bvh: warning: frame rate 120 Hz contradicted by the data: the body's centre falls at up to"),
            std::string::npos) << what;
  EXPECT_NE(what.find("(likely 60 Hz or lower); pass --source-fps 60 if so"), std::string::npos) << what;
  HumanMotion fine = hopping(120, 1);
  check_frame_rate_against_data(fine);
  EXPECT_TRUE(fine.diagnostics.empty());
}

TEST(SourceChecks, RepeatsWarnWithTheLikelyRate) {
  HumanMotion m = moving(200, 120, 1);
  check_frame_rate_against_data(m);
  ASSERT_EQ(m.diagnostics.warning_count(), 1u);
  EXPECT_EQ(m.diagnostics.items().front().to_string(),
            "clip.bvh: warning: frame rate 120 Hz contradicted by the data: every 2nd frame repeats its predecessor (100 of "
            "200 frames; likely 60 Hz); pass --source-fps 60 if so");
  HumanMotion tripled = moving(300, 90, 2);
  check_frame_rate_against_data(tripled);
  ASSERT_EQ(tripled.diagnostics.warning_count(), 1u);
  EXPECT_NE(tripled.diagnostics.items().front().to_string().find("every frame is held for 3 frames"), std::string::npos);
}

TEST(SourceChecks, CgspeedCmuClipsAt120HzGetANote) {
  HumanMotion m = moving(200, 120, 0);
  m.source.profile = "cmu_daz";
  m.source.file_fps = 120;
  check_frame_rate_against_data(m);
  ASSERT_EQ(m.diagnostics.items().size(), 1u);
  EXPECT_EQ(m.diagnostics.warning_count(), 0u);
  EXPECT_NE(m.diagnostics.items().front().to_string().find("pass --source-fps 60"), std::string::npos);
  HumanMotion other = moving(200, 120, 0);
  other.source.profile = "mixamo";
  other.source.file_fps = 120;
  check_frame_rate_against_data(other);
  EXPECT_TRUE(other.diagnostics.empty());
}

}  // namespace
}  // namespace rt
