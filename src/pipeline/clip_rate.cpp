#include "retarget/pipeline/clip_rate.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "retarget/core/error.hpp"
#include "clip_frame_arrays.hpp"

namespace rt {

GridSample grid_sample(int k, double fps_in, double fps_out, int T) {
  GridSample g;
  const double s = std::min(k / fps_out * fps_in, static_cast<double>(T - 1));
  g.i = std::min(static_cast<int>(std::floor(s)), T - 1);
  g.j = std::min(g.i + 1, T - 1);
  g.a = s - g.i;
  return g;
}

int grid_frames(int T, double fps_in, double fps_out) {
  RT_DEMAND(T > 0 && fps_in > 0 && fps_out > 0, "grid_frames: empty clip or rate");
  return static_cast<int>(std::floor((T - 1) / fps_in * fps_out + 1e-9)) + 1;
}

MatX resample_configurations(const MatX& q, double fps_in, double fps_out) {
  const int T = static_cast<int>(q.cols()), T_out = grid_frames(T, fps_in, fps_out);
  MatX out(q.rows(), T_out);
  for (int k = 0; k < T_out; ++k) {
    const GridSample g = grid_sample(k, fps_in, fps_out, T);
    out.col(k) = (1 - g.a) * q.col(g.i) + g.a * q.col(g.j);
    const Quat Qi(q(3, g.i), q(4, g.i), q(5, g.i), q(6, g.i)), Qj(q(3, g.j), q(4, g.j), q(5, g.j), q(6, g.j));
    const Quat Q = Qi.slerp(g.a, Qj).normalized();
    out.col(k).segment<4>(3) << Q.w(), Q.x(), Q.y(), Q.z();
  }
  return out;
}

std::vector<std::uint8_t> resample_contact(const std::vector<std::uint8_t>& contact, double fps_in, double fps_out, int T_out) {
  const int T = static_cast<int>(contact.size());
  std::vector<std::uint8_t> out(static_cast<std::size_t>(T_out), 0);
  if (T == 0) return out;
  std::vector<std::uint8_t> sampled(static_cast<std::size_t>(T), 0);
  for (int k = 0; k < T_out; ++k) {
    const int n = grid_sample(k, fps_in, fps_out, T).nearest();
    out[static_cast<std::size_t>(k)] = contact[static_cast<std::size_t>(n)];
    sampled[static_cast<std::size_t>(n)] = 1;
  }
  for (int b = 0; b < T;) {
    if (!contact[static_cast<std::size_t>(b)]) {
      ++b;
      continue;
    }
    int e = b;
    bool seen = false;
    for (; e < T && contact[static_cast<std::size_t>(e)]; ++e) seen = seen || sampled[static_cast<std::size_t>(e)];
    if (!seen) {
      const double t_mid = 0.5 * (b + e - 1) / fps_in;
      out[static_cast<std::size_t>(std::clamp(static_cast<int>(std::lround(t_mid * fps_out)), 0, T_out - 1))] = 1;
    }
    b = e;
  }
  return out;
}

namespace {

// Columns of a per-frame matrix on the new grid, linearly.
template <class M>
M resample_columns(const M& m, double fps_in, double fps_out, int T_out) {
  const int T = static_cast<int>(m.cols());
  M out(m.rows(), T_out);
  for (int k = 0; k < T_out; ++k) {
    const GridSample g = grid_sample(k, fps_in, fps_out, T);
    out.col(k) = (1 - g.a) * m.col(g.i) + g.a * m.col(g.j);
  }
  return out;
}

// Entries of a per-frame vector on the new grid, from the nearest frame.
template <class V>
V resample_nearest(const V& v, double fps_in, double fps_out, int T_out) {
  const int T = static_cast<int>(v.size());
  V out;
  out.reserve(static_cast<std::size_t>(T_out));
  for (int k = 0; k < T_out; ++k) out.push_back(v[static_cast<std::size_t>(grid_sample(k, fps_in, fps_out, T).nearest())]);
  return out;
}

// Puts each per-frame array on the new grid (clip_frame_arrays.hpp).
struct ResampleFrames {
  double fps_in, fps_out;
  int T, T_out;
  template <typename M>
  void columns(M& m) const { m = resample_columns(m, fps_in, fps_out, T_out); }
  void configurations(MatX& q) const { q = resample_configurations(q, fps_in, fps_out); }
  template <typename E>
  void entries(std::vector<E>& v) const { v = resample_nearest(v, fps_in, fps_out, T_out); }
  void contact(std::vector<std::uint8_t>& c) const { c = resample_contact(c, fps_in, fps_out, T_out); }
  // Positions interpolated where both neighbouring samples are valid, else the nearest frame's.
  void track(LandmarkTrack& t) const {
    Mat3X p(3, T_out);
    for (int k = 0; k < T_out; ++k) {
      const GridSample g = grid_sample(k, fps_in, fps_out, T);
      const bool both = t.valid(g.i) && t.valid(g.j);
      p.col(k) = both ? Vec3((1 - g.a) * t.p_W.col(g.i) + g.a * t.p_W.col(g.j)) : Vec3(t.p_W.col(g.nearest()));
    }
    t.p_W = std::move(p);
    entries(t.state);
    if (t.has_orientation) entries(t.R_W);
  }
};

}  // namespace

Clip resample_clip_frames(const Clip& clip, double fps_out) {
  const RobotMotion& m = clip.motion;
  const int T = m.num_frames();
  RT_DEMAND(T > 0 && m.fps > 0 && fps_out > 0, "resample_clip_frames: no robot motion or rate");
  const double fps_in = m.fps;
  Clip out;
  out.name = clip.name;
  out.flat_contact_offset = clip.flat_contact_offset;
  out.motion = m;
  out.motion.fps = fps_out;
  out.contacts = clip.contacts;
  out.targets = clip.targets;
  out.com_replanned_W = clip.com_replanned_W;
  out.cop_predicted_W = clip.cop_predicted_W;
  ResampleFrames resample{fps_in, fps_out, T, grid_frames(T, fps_in, fps_out)};
  detail::each_frame_array(out, resample);
  out.lead_in_frames = static_cast<int>(std::lround(clip.lead_in_frames / fps_in * fps_out));
  out.lead_out_frames = static_cast<int>(std::lround(clip.lead_out_frames / fps_in * fps_out));
  return out;
}

}  // namespace rt
