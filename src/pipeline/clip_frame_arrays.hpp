#pragma once
/// Every per-frame array of a clip at the robot motion's rate, listed once, for the operations that
/// change a clip's frames (hold_clip_ends, resample_clip_frames): a per-frame array added to Clip is
/// added here, and both follow. Private to the pipeline library.

#include "retarget/pipeline/clip.hpp"

namespace rt::detail {

/// Calls `visit` with every array of `clip` that has the robot motion's T frames (T taken before the
/// first call, so a visitor may change the frame count), by kind:
///   visit.configurations(MatX&)               nq x T configurations (motion, per-frame IK copy)
///   visit.columns(M&)                         other per-frame columns: landmark errors (a 1 x T
///                                             row), re-planned COM, predicted COP
///   visit.entries(std::vector<E>&)            per-frame labels (worst landmark)
///   visit.contact(std::vector<std::uint8_t>&) one foot's contact flags
///   visit.track(LandmarkTrack&)               a present landmark target track: positions, states
///                                             and (if it has them) orientations
template <typename Visitor>
void each_frame_array(Clip& clip, Visitor& visit) {
  RobotMotion& m = clip.motion;
  const int T = m.num_frames();
  visit.configurations(m.q);
  if (m.q_per_frame_ik.cols() == T) visit.configurations(m.q_per_frame_ik);
  if (m.landmark_error_m.size() == T) {
    Eigen::RowVectorXd e = m.landmark_error_m.transpose();
    visit.columns(e);
    m.landmark_error_m = e.transpose();
  }
  if (static_cast<int>(m.worst_landmark.size()) == T) visit.entries(m.worst_landmark);
  for (auto& c : clip.contacts.in_contact)
    if (static_cast<int>(c.size()) == T) visit.contact(c);
  for (LandmarkTrack& track : clip.targets.tracks)
    if (track.present && track.p_W.cols() == T) visit.track(track);
  if (clip.com_replanned_W.cols() == T) visit.columns(clip.com_replanned_W);
  if (clip.cop_predicted_W.cols() == T) visit.columns(clip.cop_predicted_W);
}

}  // namespace rt::detail
