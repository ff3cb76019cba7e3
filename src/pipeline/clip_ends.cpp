#include "retarget/pipeline/clip_ends.hpp"

#include <type_traits>
#include <utility>

#include "retarget/core/error.hpp"

namespace rt {

namespace {

// Applies `columns` to every per-frame matrix (frames as columns) and `entries` to every per-frame
// vector of the clip that has the robot motion's T frames.
template <typename Columns, typename Entries>
void each_frame_array(Clip& clip, Columns columns, Entries entries) {
  RobotMotion& m = clip.motion;
  const int T = m.num_frames();
  columns(m.q);
  if (m.q_per_frame_ik.cols() == T) columns(m.q_per_frame_ik);
  if (m.landmark_error_m.size() == T) {
    Eigen::RowVectorXd e = m.landmark_error_m.transpose();
    columns(e);
    m.landmark_error_m = e.transpose();
  }
  if (static_cast<int>(m.worst_landmark.size()) == T) entries(m.worst_landmark);
  for (auto& c : clip.contacts.in_contact)
    if (static_cast<int>(c.size()) == T) entries(c);
  for (LandmarkTrack& track : clip.targets.tracks) {
    if (!track.present || track.p_W.cols() != T) continue;
    columns(track.p_W);
    entries(track.state);
    if (track.has_orientation) entries(track.R_W);
  }
  if (clip.com_replanned_W.cols() == T) columns(clip.com_replanned_W);
  if (clip.cop_predicted_W.cols() == T) columns(clip.cop_predicted_W);
}

}  // namespace

void hold_clip_ends(Clip& clip, int before, int after) {
  RT_DEMAND(before >= 0 && after >= 0, "hold_clip_ends: negative frame count");
  if (before == 0 && after == 0) return;
  RT_DEMAND(clip.motion.num_frames() > 0, "hold_clip_ends: no robot motion");
  each_frame_array(
      clip,
      [&](auto& m) {
        const Eigen::Index T = m.cols();
        std::decay_t<decltype(m)> out(m.rows(), before + T + after);
        out.leftCols(before) = m.col(0).replicate(1, before);
        out.middleCols(before, T) = m;
        out.rightCols(after) = m.col(T - 1).replicate(1, after);
        m = std::move(out);
      },
      [&](auto& v) {
        const auto first = v.front(), last = v.back();
        v.insert(v.begin(), static_cast<std::size_t>(before), first);
        v.insert(v.end(), static_cast<std::size_t>(after), last);
      });
  clip.lead_in_frames += before;
  clip.lead_out_frames += after;
}

}  // namespace rt
