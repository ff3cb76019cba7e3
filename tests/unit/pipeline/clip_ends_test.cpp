// hold_clip_ends (com-plan's standing lead-in and lead-out): every per-frame array of the clip at
// the source rate grows by copies of its end frames, in step, and the source motion stays as parsed.

#include <gtest/gtest.h>

#include "retarget/pipeline/clip_ends.hpp"

namespace rt {
namespace {

Clip three_frame_clip() {
  Clip clip;
  clip.human.num_frames = 3;
  clip.motion.fps = 30;
  clip.motion.q = MatX(8, 3);
  clip.motion.q.setZero();
  clip.motion.q.row(0) << 1, 2, 3;        // root x
  clip.motion.q.row(3).setOnes();         // root quaternion w
  clip.motion.q.row(7) << 0.1, 0.2, 0.3;  // one joint
  clip.motion.q_per_frame_ik = clip.motion.q;
  clip.motion.landmark_error_m = Vec3(0.01, 0.02, 0.03);
  clip.motion.worst_landmark = {4, 5, 6};
  clip.contacts.in_contact = {{{1, 0, 0}, {1, 1, 0}}};
  LandmarkTrack& pelvis = clip.targets[Landmark::Pelvis];
  pelvis.present = true;
  pelvis.p_W = Mat3X::Zero(3, 3);
  pelvis.p_W.row(0) << 10, 20, 30;
  pelvis.state = {SampleState::Measured, SampleState::Interpolated, SampleState::Missing};
  pelvis.has_orientation = true;
  pelvis.R_W = {Quat::Identity(), Quat(0, 1, 0, 0), Quat(0, 0, 1, 0)};
  return clip;
}

TEST(HoldClipEnds, RepeatsTheEndFramesInEveryPerFrameArray) {
  Clip clip = three_frame_clip();
  hold_clip_ends(clip, 2, 1);
  EXPECT_EQ(clip.lead_in_frames, 2);
  EXPECT_EQ(clip.lead_out_frames, 1);
  ASSERT_EQ(clip.motion.num_frames(), 6);
  EXPECT_EQ(clip.human.num_frames, 3);  // the source is not touched
  const std::vector<double> x{1, 1, 1, 2, 3, 3};
  for (int f = 0; f < 6; ++f) EXPECT_EQ(clip.motion.q(0, f), x[static_cast<std::size_t>(f)]) << f;
  EXPECT_EQ(clip.motion.q(7, 0), 0.1);
  EXPECT_EQ(clip.motion.q(7, 5), 0.3);
  EXPECT_EQ(clip.motion.q_per_frame_ik, clip.motion.q);
  EXPECT_EQ(clip.motion.landmark_error_m.size(), 6);
  EXPECT_EQ(clip.motion.landmark_error_m[1], 0.01);
  EXPECT_EQ(clip.motion.landmark_error_m[5], 0.03);
  EXPECT_EQ(clip.motion.worst_landmark, (std::vector<int>{4, 4, 4, 5, 6, 6}));
  EXPECT_EQ(clip.contacts.in_contact[0], (std::vector<std::uint8_t>{1, 1, 1, 0, 0, 0}));
  EXPECT_EQ(clip.contacts.in_contact[1], (std::vector<std::uint8_t>{1, 1, 1, 1, 0, 0}));
  const LandmarkTrack& pelvis = clip.targets[Landmark::Pelvis];
  ASSERT_EQ(pelvis.p_W.cols(), 6);
  EXPECT_EQ(pelvis.p_W(0, 0), 10);
  EXPECT_EQ(pelvis.p_W(0, 3), 20);
  EXPECT_EQ(pelvis.p_W(0, 5), 30);
  EXPECT_EQ(pelvis.state.size(), 6u);
  EXPECT_EQ(pelvis.state[5], SampleState::Missing);
  ASSERT_EQ(pelvis.R_W.size(), 6u);
  EXPECT_EQ(pelvis.R_W[5].y(), 1);
  EXPECT_FALSE(clip.targets[Landmark::Head].present);
  EXPECT_EQ(clip.com_replanned_W.cols(), 0);  // absent stays absent
}

TEST(HoldClipEnds, AddsUpAndLeavesAClipWithoutLeadAsItWas) {
  Clip clip = three_frame_clip();
  const MatX q = clip.motion.q;
  hold_clip_ends(clip, 0, 0);
  EXPECT_EQ(clip.motion.q, q);
  EXPECT_EQ(clip.lead_in_frames, 0);
  hold_clip_ends(clip, 1, 0);
  hold_clip_ends(clip, 1, 2);
  EXPECT_EQ(clip.lead_in_frames, 2);
  EXPECT_EQ(clip.lead_out_frames, 2);
  EXPECT_EQ(clip.motion.num_frames(), 7);
  EXPECT_EQ(clip.contacts.in_contact[0].size(), 7u);
}

}  // namespace
}  // namespace rt
