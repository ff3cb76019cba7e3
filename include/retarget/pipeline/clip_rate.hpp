#pragma once
/// A clip's per-frame arrays on another frame rate over the same time span: the resample pass's
/// sampling (design.md §5) for the arrays a pass works on, so that a pass can work on the grid the
/// motion is exported at (com-plan plans the ZMP, a second derivative, on the grid where it is
/// measured). Frame k of the new grid is at t = k / fps_out; a grid over T frames at fps_in has
/// ⌊(T − 1) / fps_in · fps_out⌋ + 1 frames (its last frame is at or before the clip's last).

#include <cstdint>
#include <vector>

#include "retarget/pipeline/clip.hpp"

namespace rt {

/// Where frame k of the new grid falls among the T source frames: between frames i and j = i + 1
/// (clamped to the clip), at weight a ∈ [0, 1) of j.
struct GridSample {
  int i = 0, j = 0;
  double a = 0;
  int nearest() const { return a < 0.5 ? i : j; }
};
GridSample grid_sample(int k, double fps_in, double fps_out, int T);
int grid_frames(int T, double fps_in, double fps_out);

/// Configurations (nq x T, robot_model.hpp convention) on the new grid: positions and joint angles
/// linearly, the root quaternion by slerp.
MatX resample_configurations(const MatX& q, double fps_in, double fps_out);

/// Contact labels on the new grid (T_out frames): each from its nearest source frame; a stance no
/// new frame samples (shorter than the new period, or after the last new frame) is kept on the
/// new frame nearest to its middle, so the new schedule has every touchdown the source has.
std::vector<std::uint8_t> resample_contact(const std::vector<std::uint8_t>& contact, double fps_in, double fps_out, int T_out);

/// A copy of the clip's per-frame arrays (robot motion and its per-frame IK copy, landmark errors,
/// contacts, landmark targets, re-planned COM and predicted COP) on a `fps_out` grid, with its
/// name, flat-contact offsets and lead frames (rounded to the new rate). The source motion
/// (`human`), the reference and the diagnostics are not copied. Landmark targets are interpolated
/// where both neighbouring samples are valid and otherwise taken from the nearest frame, as are
/// their states and orientations.
Clip resample_clip_frames(const Clip& clip, double fps_out);

}  // namespace rt
