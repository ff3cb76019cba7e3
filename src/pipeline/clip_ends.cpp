#include "retarget/pipeline/clip_ends.hpp"

#include "retarget/core/error.hpp"

namespace rt {

namespace {

template <typename Matrix>
void hold_columns(Matrix& m, int before, int after) {
  const Eigen::Index T = m.cols();
  if (T == 0) return;
  Matrix out(m.rows(), before + T + after);
  out.leftCols(before) = m.col(0).replicate(1, before);
  out.middleCols(before, T) = m;
  out.rightCols(after) = m.col(T - 1).replicate(1, after);
  m = std::move(out);
}

template <typename T>
void hold_entries(std::vector<T>& v, int before, int after) {
  if (v.empty()) return;
  const T first = v.front(), last = v.back();
  v.insert(v.begin(), static_cast<std::size_t>(before), first);
  v.insert(v.end(), static_cast<std::size_t>(after), last);
}

template <typename Matrix>
void drop_columns(Matrix& m, int before, int after) {
  if (m.cols() == 0) return;
  Matrix out = m.middleCols(before, m.cols() - before - after);
  m = std::move(out);
}

template <typename T>
void drop_entries(std::vector<T>& v, int before, int after) {
  if (v.empty()) return;
  v.erase(v.end() - after, v.end());
  v.erase(v.begin(), v.begin() + before);
}

}  // namespace

void hold_clip_ends(Clip& clip, int before, int after) {
  RT_DEMAND(before >= 0 && after >= 0, "hold_clip_ends: negative frame count");
  if (before == 0 && after == 0) return;
  RobotMotion& m = clip.motion;
  const int T = m.num_frames();
  RT_DEMAND(T > 0, "hold_clip_ends: no robot motion");
  hold_columns(m.q, before, after);
  if (m.q_per_frame_ik.cols() == T) hold_columns(m.q_per_frame_ik, before, after);
  if (m.landmark_error_m.size() == T) {
    VecX e(before + T + after);
    e << VecX::Constant(before, m.landmark_error_m[0]), m.landmark_error_m, VecX::Constant(after, m.landmark_error_m[T - 1]);
    m.landmark_error_m = std::move(e);
  }
  if (static_cast<int>(m.worst_landmark.size()) == T) hold_entries(m.worst_landmark, before, after);
  for (auto& c : clip.contacts.in_contact)
    if (static_cast<int>(c.size()) == T) hold_entries(c, before, after);
  for (LandmarkTrack& track : clip.targets.tracks) {
    if (!track.present || track.p_W.cols() != T) continue;
    hold_columns(track.p_W, before, after);
    hold_entries(track.state, before, after);
    if (track.has_orientation) hold_entries(track.R_W, before, after);
  }
  if (clip.com_replanned_W.cols() == T) hold_columns(clip.com_replanned_W, before, after);
  if (clip.cop_predicted_W.cols() == T) hold_columns(clip.cop_predicted_W, before, after);
  clip.lead_in_frames += before;
  clip.lead_out_frames += after;
}

void drop_clip_ends(Clip& clip, int before, int after) {
  RT_DEMAND(before >= 0 && after >= 0 && before <= clip.lead_in_frames && after <= clip.lead_out_frames,
            "drop_clip_ends: more frames than the clip's lead");
  if (before == 0 && after == 0) return;
  RobotMotion& m = clip.motion;
  const int T = m.num_frames();
  drop_columns(m.q, before, after);
  if (m.q_per_frame_ik.cols() == T) drop_columns(m.q_per_frame_ik, before, after);
  if (m.landmark_error_m.size() == T) {
    VecX e = m.landmark_error_m.segment(before, T - before - after);
    m.landmark_error_m = std::move(e);
  }
  if (static_cast<int>(m.worst_landmark.size()) == T) drop_entries(m.worst_landmark, before, after);
  for (auto& c : clip.contacts.in_contact)
    if (static_cast<int>(c.size()) == T) drop_entries(c, before, after);
  for (LandmarkTrack& track : clip.targets.tracks) {
    if (!track.present || track.p_W.cols() != T) continue;
    drop_columns(track.p_W, before, after);
    drop_entries(track.state, before, after);
    if (track.has_orientation) drop_entries(track.R_W, before, after);
  }
  if (clip.com_replanned_W.cols() == T) drop_columns(clip.com_replanned_W, before, after);
  if (clip.cop_predicted_W.cols() == T) drop_columns(clip.cop_predicted_W, before, after);
  clip.lead_in_frames -= before;
  clip.lead_out_frames -= after;
}

}  // namespace rt
