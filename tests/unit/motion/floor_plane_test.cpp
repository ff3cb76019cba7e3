#include "retarget/motion/floor_plane.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "retarget/motion/normalize.hpp"
#include "support/motion_builder.hpp"

namespace rt {
namespace {

// Feet stepping along x on a floor z = slope·x (+ an offset), with a still foot held high in the air
// for a while (an outlier the fit must ignore).
HumanMotion walk_on(double slope_x, double slope_y = 0) {
  HumanMotion h;
  h.source.path = "walk";
  h.fps = 100;
  h.num_frames = 400;
  const int T = h.num_frames;
  auto track = [&](Landmark l) -> LandmarkTrack& { return test::measured_track(h, l); };
  for (int side = 0; side < 2; ++side) {
    LandmarkTrack& ankle = track(side ? Landmark::RightAnkle : Landmark::LeftAnkle);
    LandmarkTrack& knee = track(side ? Landmark::RightKnee : Landmark::LeftKnee);
    LandmarkTrack& hip = track(side ? Landmark::RightHip : Landmark::LeftHip);
    for (int f = 0; f < T; ++f) {
      const double t = f / h.fps + 0.5 * side;
      const double cycle = t - std::floor(t);
      const double s = cycle < 0.6 ? 0.0 : (cycle - 0.6) / 0.4;
      const double x = 1.2 * (std::floor(t) + s * s * (3 - 2 * s)), y = side ? -0.1 : 0.1;
      double lift = 0.1 * std::sin(M_PI * s);
      if (side == 1 && f >= 300) lift = 0.3;  // still, in the air
      const double floor = slope_x * x + slope_y * y + 0.02;
      ankle.p_W.col(f) = Vec3(x, y, floor + 0.08 + lift);
      knee.p_W.col(f) = Vec3(x, y, floor + 0.5 + lift);
      hip.p_W.col(f) = Vec3(x, y, floor + 0.9 + lift);
    }
  }
  return h;
}

TEST(FloorPlane, FindsTheSlopeUnderTheFeet) {
  const double slope = std::tan(2.0 * M_PI / 180);
  const FloorPlane p = estimate_floor_plane(walk_on(slope));
  EXPECT_NEAR(p.a, slope, 0.002);
  EXPECT_NEAR(p.tilt_deg, 2.0, 0.1);
  EXPECT_LT(p.unevenness_m, 0.01);
  EXPECT_GT(p.candidates, 100);
  EXPECT_NEAR(human_leg_length(walk_on(0)), 0.82, 1e-9);
}

TEST(FloorPlane, NoSlopeAlongDirectionsTheFeetDoNotSpan) {
  // The feet are only 0.2 m apart sideways: a sideways slope cannot be told from the data.
  const FloorPlane p = estimate_floor_plane(walk_on(0, 0.2));
  EXPECT_NEAR(p.b, 0.0, 1e-9);
}

TEST(FloorPlane, NormalizeLevelsATiltedFloorAndWarns) {
  HumanMotion h = walk_on(std::tan(3.0 * M_PI / 180));
  NormalizeOptions o;
  o.align_start = false;
  normalize_motion(h, o);
  EXPECT_NEAR(h.source.floor_tilt_deg, 3.0, 0.15);
  EXPECT_NEAR(estimate_floor_plane(h).tilt_deg, 0.0, 0.1);
  bool warned = false;
  for (const Diagnostic& d : h.diagnostics.items()) warned = warned || d.to_string().find("tilted") != std::string::npos;
  EXPECT_TRUE(warned);
  // The stance ankles now sit at the same height at both ends of the walk.
  const LandmarkTrack& ankle = h[Landmark::LeftAnkle];
  EXPECT_NEAR(ankle.p_W(2, 10), ankle.p_W(2, 310), 0.002);
  // A level floor is left alone.
  HumanMotion flat = walk_on(0);
  normalize_motion(flat, o);
  EXPECT_EQ(flat.source.floor_tilt_deg, 0.0);
}

}  // namespace
}  // namespace rt
