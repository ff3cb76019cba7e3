#include "retarget/passes/retime.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

HumanMotion retime_motion(const HumanMotion& in, double S) {
  if (!(S >= 0.05 && S <= 20)) throw InputError("--time-scale", "must be in [0.05, 20], got " + std::to_string(S));
  if (S == 1.0 || in.num_frames < 2) return in;
  const int T = in.num_frames;
  const double duration = (T - 1) / in.fps;
  check_clip_duration(duration * S, "--time-scale", format("the clip played %g times slower", S));
  const int T_out = static_cast<int>(std::floor(duration * S * in.fps + 1e-9)) + 1;
  HumanMotion out = in;
  out.num_frames = T_out;
  out.time_scale = in.time_scale * S;
  for (Landmark l : all_landmarks()) {
    const LandmarkTrack& a = in[l];
    LandmarkTrack& b = out[l];
    if (!a.present) continue;
    b.p_W.resize(3, T_out);
    b.state.resize(static_cast<std::size_t>(T_out));
    if (a.has_orientation) b.R_W.resize(static_cast<std::size_t>(T_out));
    for (int k = 0; k < T_out; ++k) {
      const double s = std::min(k / S, static_cast<double>(T - 1));
      const int i = std::min(static_cast<int>(s), T - 1), j = std::min(i + 1, T - 1);
      const double w = s - i;
      b.p_W.col(k) = (1 - w) * a.p_W.col(i) + w * a.p_W.col(j);
      const SampleState si = a.state[static_cast<std::size_t>(i)], sj = a.state[static_cast<std::size_t>(j)];
      // Missing (0) < Measured (1) < Interpolated (2) in validity terms: take the worse neighbour.
      auto rank = [](SampleState st) { return st == SampleState::Missing ? 0 : st == SampleState::Interpolated ? 1 : 2; };
      b.state[static_cast<std::size_t>(k)] = w == 0 ? si : (rank(si) <= rank(sj) ? si : sj);
      if (a.has_orientation)
        b.R_W[static_cast<std::size_t>(k)] = a.R_W[static_cast<std::size_t>(i)].slerp(w, a.R_W[static_cast<std::size_t>(j)]).normalized();
    }
  }
  return out;
}

RetimePass::RetimePass() {
  table_.add("time_scale", options_.time_scale, "> 1 slows the clip down (2 = half speed), < 1 speeds it up",
             {0.05, 20, ""});
}

void RetimePass::run(Clip& clip, PassContext& ctx) {
  if (options_.time_scale == 1.0) return;
  const int before = clip.human.num_frames;
  clip.human = retime_motion(clip.human, options_.time_scale);
  ctx.statistics.set("time-scale", options_.time_scale);
  ctx.statistics.set("frames", clip.human.num_frames, "frames", "from " + std::to_string(before));
}

}  // namespace rt
