// Plausibility checks of loaded clips (source_checks.hpp): stature (wrong units) and repeated
// frames (a stated rate higher than the data's).

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace rt
