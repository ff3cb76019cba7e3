#include "retarget/passes/label_contacts.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "retarget/passes/retime.hpp"
#include "support/motion_builder.hpp"

namespace rt {
namespace {

// Both feet as tracks: `down` frames at rest and still, the others `up_height` high and moving.
std::array<FootTrack, 2> tracks(int T, const std::array<std::vector<std::uint8_t>, 2>& down, double up_height = 0.10,
                                double up_speed = 1.5) {
  std::array<FootTrack, 2> t;
  for (int foot = 0; foot < 2; ++foot)
    for (int f = 0; f < T; ++f) {
      const bool d = down[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)];
      t[static_cast<std::size_t>(foot)].height_m.push_back(d ? 0.0 : up_height);
      t[static_cast<std::size_t>(foot)].speed_mps.push_back(d ? 0.0 : up_speed);
    }
  return t;
}

std::vector<std::uint8_t> run(int T, int begin, int end) {
  std::vector<std::uint8_t> v(static_cast<std::size_t>(T), 0);
  for (int f = begin; f < end; ++f) v[static_cast<std::size_t>(f)] = 1;
  return v;
}

int frames_without_stance(const ContactSchedule& s) {
  int n = 0;
  for (std::size_t f = 0; f < s.in_contact[0].size(); ++f) n += !s.in_contact[0][f] && !s.in_contact[1][f];
  return n;
}

int overlap(const ContactSchedule& s, int from, int to) {
  int n = 0;
  for (int f = from; f < to; ++f) n += s.in_contact[0][static_cast<std::size_t>(f)] && s.in_contact[1][static_cast<std::size_t>(f)];
  return n;
}

const double kFps = 100, kLeg = 0.85;

TEST(LabelFeet, AWeightTransferWithAGapGetsTheMinimumDoubleSupport) {
  const int T = 120;
  // Left down until 50, right down from 56: in the gap both feet are low but still moving fast
  // (a quick heel strike): not a flight.
  std::array<FootTrack, 2> t = tracks(T, {run(T, 0, 50), run(T, 56, T)});
  for (int f = 50; f < 56; ++f) {
    t[0].height_m[static_cast<std::size_t>(f)] = 0.02;
    t[1].height_m[static_cast<std::size_t>(f)] = 0.02;
  }
  const ContactLabelling l = label_feet(t, kFps, kLeg, {});
  EXPECT_EQ(frames_without_stance(l.schedule), 0);
  EXPECT_EQ(l.flight_phases, 0);
  EXPECT_GT(l.filled_frames, 0);
  EXPECT_GE(overlap(l.schedule, 30, 80), 8);  // 0.08 s at 100 fps
}

TEST(LabelFeet, AGapBetweenTwoStancesOfOneFootGoesToTheFootThatIsStill) {
  const int T = 100;
  // Left down until 40 and from 60; in between it kicks (8 cm up, 3 m/s). The right foot swings
  // until 40 and after 60, and in between hovers still, 3.5 cm up (above the touch-down height):
  // neither passes the thresholds, yet the right foot is the one that carries the weight.
  std::array<FootTrack, 2> t = tracks(T, {run(T, 0, 40), run(T, 0, 0)});
  for (int f = 60; f < T; ++f) t[0].height_m[static_cast<std::size_t>(f)] = 0, t[0].speed_mps[static_cast<std::size_t>(f)] = 0;
  for (int f = 40; f < 60; ++f) {
    t[0].height_m[static_cast<std::size_t>(f)] = 0.08, t[0].speed_mps[static_cast<std::size_t>(f)] = 3.0;
    t[1].height_m[static_cast<std::size_t>(f)] = 0.035, t[1].speed_mps[static_cast<std::size_t>(f)] = 0.0;
  }
  const ContactLabelling l = label_feet(t, kFps, kLeg, {});
  EXPECT_EQ(l.flight_phases, 0);
  EXPECT_EQ(frames_without_stance(l.schedule), 0);
  for (int f = 45; f < 55; ++f) {
    EXPECT_FALSE(l.schedule.in_contact[0][static_cast<std::size_t>(f)]) << f;
    EXPECT_TRUE(l.schedule.in_contact[1][static_cast<std::size_t>(f)]) << f;
  }
  EXPECT_GE(overlap(l.schedule, 30, 45), 8);  // both weight transfers keep their double support
  EXPECT_GE(overlap(l.schedule, 55, 70), 8);
  // Two feet alike in the gap (both low, both moving): no handing over and back, the left foot keeps it.
  for (int f = 40; f < 60; ++f)
    for (auto& ft : t) ft.height_m[static_cast<std::size_t>(f)] = 0.04, ft.speed_mps[static_cast<std::size_t>(f)] = 1.0;
  const ContactLabelling alike = label_feet(t, kFps, kLeg, {});
  for (int f = 40; f < 60; ++f) {
    EXPECT_TRUE(alike.schedule.in_contact[0][static_cast<std::size_t>(f)]) << f;
    EXPECT_FALSE(alike.schedule.in_contact[1][static_cast<std::size_t>(f)]) << f;
  }
}

TEST(LabelFeet, AShortDoubleSupportIsWidenedSymmetrically) {
  const int T = 120;
  const ContactLabelling l = label_feet(tracks(T, {run(T, 0, 52), run(T, 50, T)}), kFps, kLeg, {});
  EXPECT_GE(overlap(l.schedule, 0, T), 8);
  EXPECT_LE(overlap(l.schedule, 0, T), 9);
  EXPECT_EQ(l.widened_transfers, 1);
  // Both sides moved: the left foot stays longer, the right one lands earlier.
  EXPECT_TRUE(l.schedule.in_contact[0][52]);
  EXPECT_TRUE(l.schedule.in_contact[1][48]);
  // A long double support is left alone.
  const ContactLabelling wide = label_feet(tracks(T, {run(T, 0, 70), run(T, 50, T)}), kFps, kLeg, {});
  EXPECT_EQ(wide.widened_transfers, 0);
  EXPECT_EQ(overlap(wide.schedule, 0, T), 20);
}

TEST(LabelFeet, ARealFlightStaysAFlight) {
  const int T = 120;
  // A jump: both feet high for 0.2 s.
  const ContactLabelling l = label_feet(tracks(T, {run(T, 0, 50) , run(T, 0, 50)}), kFps, kLeg, {});
  std::array<FootTrack, 2> t = tracks(T, {run(T, 0, 50), run(T, 0, 50)});
  for (int f = 70; f < T; ++f)
    for (auto& ft : t) ft.height_m[static_cast<std::size_t>(f)] = 0, ft.speed_mps[static_cast<std::size_t>(f)] = 0;
  const ContactLabelling jump = label_feet(t, kFps, kLeg, {});
  EXPECT_EQ(jump.flight_phases, 1);
  EXPECT_EQ(jump.flight_frames, 20);
  EXPECT_EQ(frames_without_stance(jump.schedule), 20);
  EXPECT_EQ(l.flight_phases, 1);  // lands nowhere: still a flight up to the clip's end
}

TEST(LabelFeet, ThresholdsScaleWithTheSubject) {
  const int T = 60;
  // 3 cm above rest: a contact for an adult (on below 0.035 leg lengths), not for a 0.3 m-leg child.
  std::array<FootTrack, 2> t = tracks(T, {run(T, 0, T), run(T, 0, T)});
  for (int f = 20; f < 40; ++f) t[0].height_m[static_cast<std::size_t>(f)] = 0.045;
  EXPECT_TRUE(label_feet(t, kFps, 0.9, {}).schedule.in_contact[0][30]);
  EXPECT_FALSE(label_feet(t, kFps, 0.3, {}).schedule.in_contact[0][30]);
}

TEST(MergeShortPhases, FillsShortSwingsThenDropsShortStances) {
  std::vector<std::uint8_t> v = {1, 1, 1, 0, 1, 1, 1, 0, 0, 0, 1, 0, 0, 0};
  EXPECT_EQ(merge_short_phases(v, 2), 2);
  EXPECT_EQ(v, (std::vector<std::uint8_t>{1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0}));
}

// A walk of a synthetic subject (leg 0.82 m): steps of 1 s, stance 0.6 s, 0.1 s double support.
HumanMotion synthetic_walk(double fps = 100, double seconds = 4) {
  HumanMotion h;
  h.source.path = "walk";
  h.fps = fps;
  h.num_frames = static_cast<int>(seconds * fps);
  const int T = h.num_frames;
  auto track = [&](Landmark l) -> LandmarkTrack& { return test::measured_track(h, l); };
  for (int side = 0; side < 2; ++side) {
    const double y = side == 0 ? 0.1 : -0.1, phase = side == 0 ? 0.0 : 0.5;
    LandmarkTrack& hip = track(side == 0 ? Landmark::LeftHip : Landmark::RightHip);
    LandmarkTrack& knee = track(side == 0 ? Landmark::LeftKnee : Landmark::RightKnee);
    LandmarkTrack& ankle = track(side == 0 ? Landmark::LeftAnkle : Landmark::RightAnkle);
    LandmarkTrack& toe = track(side == 0 ? Landmark::LeftToe : Landmark::RightToe);
    LandmarkTrack& heel = track(side == 0 ? Landmark::LeftHeel : Landmark::RightHeel);
    for (int f = 0; f < T; ++f) {
      const double t = f / fps + phase;
      const double cycle = t - std::floor(t), step = std::floor(t);
      // Stance for cycle in [0, 0.6), swing 0.4 s moving 1.2 m forward with a 10 cm lift.
      const double s = cycle < 0.6 ? 0.0 : (cycle - 0.6) / 0.4;
      const double x = 1.2 * (step + (s * s * (3 - 2 * s))) - 1.2 * phase;
      const double lift = 0.10 * std::sin(M_PI * s);
      ankle.p_W.col(f) = Vec3(x, y, 0.08 + lift);
      toe.p_W.col(f) = Vec3(x + 0.15, y, 0.02 + lift);
      heel.p_W.col(f) = Vec3(x - 0.05, y, 0.03 + lift);
      knee.p_W.col(f) = Vec3(x, y, 0.5 + lift);
      hip.p_W.col(f) = Vec3(x, y, 0.9 + lift);
    }
  }
  return h;
}

TEST(LabelContacts, AWalkHasAStanceFootOnEveryFrameAndRealisticDoubleSupport) {
  const ContactLabelling l = label_contacts(synthetic_walk(), {});
  EXPECT_EQ(frames_without_stance(l.schedule), 0);
  EXPECT_EQ(l.flight_phases, 0);
  const int T = static_cast<int>(l.schedule.in_contact[0].size());
  const double ds = static_cast<double>(overlap(l.schedule, 0, T)) / T;
  EXPECT_GT(ds, 0.12);  // 0.2 of the cycle in the data; labels lose a little at heel strike
  EXPECT_LT(ds, 0.3);
}

TEST(LabelContacts, LabelsDoNotDependOnTheTimeScale) {
  const HumanMotion h = synthetic_walk();
  const ContactSchedule base = label_contacts(h, {}).schedule;
  for (const double scale : {0.5, 2.0}) {
    const ContactSchedule slow = label_contacts(retime_motion(h, scale), {}).schedule;
    int agree = 0, total = 0;
    for (std::size_t k = 0; k < slow.in_contact[0].size(); ++k) {
      const auto f = static_cast<std::size_t>(std::lround(k / scale));
      if (f >= base.in_contact[0].size()) continue;
      for (int foot = 0; foot < 2; ++foot) {
        agree += slow.in_contact[static_cast<std::size_t>(foot)][k] == base.in_contact[static_cast<std::size_t>(foot)][f];
        ++total;
      }
    }
    EXPECT_GT(static_cast<double>(agree) / total, 0.97) << scale;
  }
}

}  // namespace
}  // namespace rt
