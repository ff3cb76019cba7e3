#include "retarget/motion/normalize.hpp"

#include <gtest/gtest.h>

#include "retarget/core/error.hpp"

namespace rt {
namespace {

// A standing figure facing +Y (left side at -X) in a Z-up frame, floor at z = 0.3, with a
// heel-less right foot and a full left foot.
HumanMotion standing_figure(int frames) {
  HumanMotion m;
  m.fps = 30;
  m.num_frames = frames;
  auto set = [&](Landmark l, Vec3 p) {
    LandmarkTrack& t = m[l];
    t.present = true;
    t.p_W = p.replicate(1, frames);
    t.state.assign(static_cast<std::size_t>(frames), SampleState::Measured);
  };
  const double floor = 0.3;
  // Facing +Y means "left" is -X.
  set(Landmark::Pelvis, {2, 5, floor + 0.95});
  set(Landmark::LeftHip, {2 - 0.1, 5, floor + 0.9});
  set(Landmark::RightHip, {2 + 0.1, 5, floor + 0.9});
  set(Landmark::Spine, {2, 5, floor + 1.15});
  set(Landmark::Chest, {2, 5, floor + 1.35});
  set(Landmark::Neck, {2, 5, floor + 1.5});
  set(Landmark::LeftShoulder, {2 - 0.18, 5, floor + 1.45});
  set(Landmark::RightShoulder, {2 + 0.18, 5, floor + 1.45});
  set(Landmark::LeftAnkle, {2 - 0.1, 5, floor + 0.08});
  set(Landmark::LeftHeel, {2 - 0.1, 5 - 0.05, floor + 0.0});
  set(Landmark::LeftToe, {2 - 0.1, 5 + 0.15, floor + 0.0});
  set(Landmark::RightAnkle, {2 + 0.1, 5, floor + 0.08});
  set(Landmark::RightToe, {2 + 0.1, 5 + 0.15, floor + 0.02});
  return m;
}

TEST(Normalize, UpAxisRotationsAreProperAndMapUpToZ) {
  for (char axis : {'x', 'y', 'z'}) {
    const Mat3 R = up_axis_to_z_up(axis);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    Vec3 up = Vec3::Zero();
    up[axis - 'x'] = 1;
    EXPECT_TRUE((R * up).isApprox(Vec3::UnitZ()));
    const Mat3 Rn = up_axis_to_z_up(axis, true);
    EXPECT_NEAR(Rn.determinant(), 1.0, 1e-12);
    EXPECT_TRUE((Rn * -up).isApprox(Vec3::UnitZ()));
  }
  EXPECT_THROW(up_axis_to_z_up('w'), InputError);
}

TEST(Normalize, FloorAlignmentAndOrientations) {
  HumanMotion m = standing_figure(10);
  normalize_motion(m);
  EXPECT_NEAR(m.source.floor_height_m, 0.3, 1e-12);
  // Pelvis above the origin, subject facing +X: the left hip is on +Y.
  EXPECT_NEAR(m[Landmark::Pelvis].p_W(0, 0), 0, 1e-12);
  EXPECT_NEAR(m[Landmark::Pelvis].p_W(1, 0), 0, 1e-12);
  EXPECT_NEAR(m[Landmark::Pelvis].p_W(2, 0), 0.95, 1e-12);
  EXPECT_NEAR(m[Landmark::LeftHip].p_W(1, 0), 0.1, 1e-12);
  EXPECT_NEAR(m[Landmark::LeftToe].p_W(0, 0), 0.15, 1e-12);
  // Upright figure: pelvis, chest and the left (heel) foot frames are identity.
  for (Landmark l : {Landmark::Pelvis, Landmark::Chest, Landmark::LeftAnkle}) {
    ASSERT_TRUE(m[l].has_orientation) << landmark_name(l);
    EXPECT_LT(m[l].R_W[0].angularDistance(Quat::Identity()), 1e-9) << landmark_name(l);
  }
  // The heel-less right foot slopes down from ankle to toe; the level correction removes it.
  ASSERT_TRUE(m[Landmark::RightAnkle].has_orientation);
  EXPECT_LT(m[Landmark::RightAnkle].R_W[0].angularDistance(Quat::Identity()), 1e-9);
}

TEST(Normalize, FloorNeedsFeet) {
  HumanMotion m = standing_figure(3);
  for (Landmark l : {Landmark::LeftAnkle, Landmark::LeftToe, Landmark::LeftHeel, Landmark::RightAnkle,
                     Landmark::RightToe})
    m[l] = LandmarkTrack{};
  EXPECT_THROW(normalize_motion(m), InputError);
}

TEST(Normalize, FloorPercentileIgnoresGlitches) {
  HumanMotion m = standing_figure(200);
  // One glitched frame with a foot far below the floor must not move the floor estimate.
  m[Landmark::LeftToe].p_W(2, 17) = -5;
  EXPECT_NEAR(estimate_floor_height(m, 0.02), 0.3, 1e-12);
}

}  // namespace
}  // namespace rt
