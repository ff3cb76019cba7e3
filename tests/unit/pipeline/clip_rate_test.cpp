// resample_clip_frames (com-plan works on the export grid): every per-frame array of the clip is
// put on the new grid alike — positions and joints linearly, the root by slerp, labels, states and
// orientations from the nearest frame, targets from the nearest frame where a neighbour is missing.

#include <gtest/gtest.h>

#include <cmath>

#include "retarget/pipeline/clip_rate.hpp"

namespace rt {
namespace {

// Four frames at 30 Hz: root x 0, 1, 2, 3 m, yaw 0, 0.2, 0.4, 0.6 rad, one joint 0.1 ... 0.4 rad.
Clip four_frame_clip() {
  Clip clip;
  clip.name = "four";
  clip.human.num_frames = 4;
  clip.motion.fps = 30;
  clip.motion.q = MatX::Zero(8, 4);
  for (int f = 0; f < 4; ++f) {
    clip.motion.q(0, f) = f;
    const Quat R(Eigen::AngleAxisd(0.2 * f, Vec3::UnitZ()));
    clip.motion.q.col(f).segment<4>(3) << R.w(), R.x(), R.y(), R.z();
    clip.motion.q(7, f) = 0.1 * (f + 1);
  }
  clip.motion.q_per_frame_ik = clip.motion.q;
  clip.motion.landmark_error_m = Eigen::Vector4d(0.01, 0.02, 0.03, 0.04);
  clip.motion.worst_landmark = {4, 5, 6, 7};
  clip.contacts.in_contact = {{{1, 1, 0, 0}, {0, 1, 1, 1}}};
  LandmarkTrack& pelvis = clip.targets[Landmark::Pelvis];
  pelvis.present = true;
  pelvis.p_W = Mat3X::Zero(3, 4);
  pelvis.p_W.row(0) << 10, 20, 30, 40;
  pelvis.state = {SampleState::Measured, SampleState::Measured, SampleState::Missing, SampleState::Measured};
  pelvis.has_orientation = true;
  pelvis.R_W = {Quat::Identity(), Quat(0, 1, 0, 0), Quat(0, 0, 1, 0), Quat(0, 0, 0, 1)};
  clip.com_replanned_W = Mat3X::Zero(3, 4);
  clip.com_replanned_W.row(1) << 0, 2, 4, 6;
  clip.lead_in_frames = 2;
  return clip;
}

TEST(ResampleClipFrames, PutsEveryPerFrameArrayOnTheNewGrid) {
  const Clip in = four_frame_clip();
  const Clip out = resample_clip_frames(in, 20);  // frames at 0, 1.5, 3 source frames
  EXPECT_EQ(out.name, "four");
  EXPECT_EQ(out.motion.fps, 20);
  ASSERT_EQ(out.motion.num_frames(), 3);
  EXPECT_EQ(grid_frames(4, 30, 20), 3);
  EXPECT_DOUBLE_EQ(out.motion.q(0, 1), 1.5);
  EXPECT_DOUBLE_EQ(out.motion.q(7, 1), 0.25);
  const Quat R(out.motion.q(3, 1), out.motion.q(4, 1), out.motion.q(5, 1), out.motion.q(6, 1));
  EXPECT_NEAR(R.angularDistance(Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()))), 0, 1e-12);  // slerp
  EXPECT_DOUBLE_EQ(out.motion.q(0, 2), 3);
  EXPECT_EQ(out.motion.q_per_frame_ik, out.motion.q);
  EXPECT_DOUBLE_EQ(out.motion.landmark_error_m[1], 0.025);
  EXPECT_EQ(out.motion.worst_landmark, (std::vector<int>{4, 6, 7}));  // a = 0.5 takes the later frame
  EXPECT_EQ(out.contacts.in_contact[0], (std::vector<std::uint8_t>{1, 0, 0}));
  EXPECT_EQ(out.contacts.in_contact[1], (std::vector<std::uint8_t>{0, 1, 1}));
  const LandmarkTrack& pelvis = out.targets[Landmark::Pelvis];
  ASSERT_EQ(pelvis.p_W.cols(), 3);
  EXPECT_EQ(pelvis.p_W(0, 1), 30);  // frame 2 is missing: the nearest sample, not a blend with it
  EXPECT_EQ(pelvis.state, (std::vector<SampleState>{SampleState::Measured, SampleState::Missing, SampleState::Measured}));
  ASSERT_EQ(pelvis.R_W.size(), 3u);
  EXPECT_EQ(pelvis.R_W[1].y(), 1);
  EXPECT_FALSE(out.targets[Landmark::Head].present);
  EXPECT_DOUBLE_EQ(out.com_replanned_W(1, 1), 3);
  EXPECT_EQ(out.cop_predicted_W.cols(), 0);  // absent stays absent
  EXPECT_EQ(out.lead_in_frames, 1);           // 2 frames at 30 Hz, rounded at 20 Hz
  EXPECT_EQ(out.human.num_frames, 0);         // the source motion is not copied
}

TEST(ResampleContact, KeepsAStanceNoNewFrameSamples) {
  // 40 Hz to 20 Hz: the new frames sample source frames 0, 2 and 4; the one-frame stance at frame 1
  // (t = 25 ms) is kept on the new frame nearest to it (t = 50 ms), the one at frame 3 likewise.
  EXPECT_EQ(resample_contact({0, 1, 0, 0, 0}, 40, 20, 3), (std::vector<std::uint8_t>{0, 1, 0}));
  EXPECT_EQ(resample_contact({0, 0, 0, 1, 0}, 40, 20, 3), (std::vector<std::uint8_t>{0, 0, 1}));
  EXPECT_EQ(resample_contact({1, 1, 1, 1, 0}, 40, 20, 3), (std::vector<std::uint8_t>{1, 1, 0}));
}

TEST(ResampleClipFrames, TheSameRateCopiesTheClip) {
  const Clip in = four_frame_clip();
  const Clip out = resample_clip_frames(in, 30);
  ASSERT_EQ(out.motion.num_frames(), 4);
  EXPECT_TRUE(out.motion.q.isApprox(in.motion.q, 1e-15));
  EXPECT_EQ(out.contacts.in_contact, in.contacts.in_contact);
  EXPECT_EQ(out.targets[Landmark::Pelvis].p_W, in.targets[Landmark::Pelvis].p_W);
  EXPECT_EQ(out.lead_in_frames, 2);
}

}  // namespace
}  // namespace rt
