#include "retarget/pipeline/clip_ends.hpp"

#include <utility>
#include <vector>

#include "retarget/core/error.hpp"
#include "clip_frame_arrays.hpp"

namespace rt {

namespace {

// Repeats the first frame `before` times and the last one `after` times.
struct HoldEnds {
  int before, after;
  template <typename M>
  void columns(M& m) const {
    const Eigen::Index T = m.cols();
    M out(m.rows(), before + T + after);
    out.leftCols(before) = m.col(0).replicate(1, before);
    out.middleCols(before, T) = m;
    out.rightCols(after) = m.col(T - 1).replicate(1, after);
    m = std::move(out);
  }
  void configurations(MatX& q) const { columns(q); }
  template <typename E>
  void entries(std::vector<E>& v) const {
    const E first = v.front(), last = v.back();
    v.insert(v.begin(), static_cast<std::size_t>(before), first);
    v.insert(v.end(), static_cast<std::size_t>(after), last);
  }
  void contact(std::vector<std::uint8_t>& c) const { entries(c); }
  void track(LandmarkTrack& t) const {
    columns(t.p_W);
    entries(t.state);
    if (t.has_orientation) entries(t.R_W);
  }
};

}  // namespace

void hold_clip_ends(Clip& clip, int before, int after) {
  RT_DEMAND(before >= 0 && after >= 0, "hold_clip_ends: negative frame count");
  if (before == 0 && after == 0) return;
  RT_DEMAND(clip.motion.num_frames() > 0, "hold_clip_ends: no robot motion");
  HoldEnds hold{before, after};
  detail::each_frame_array(clip, hold);
  clip.lead_in_frames += before;
  clip.lead_out_frames += after;
}

}  // namespace rt
