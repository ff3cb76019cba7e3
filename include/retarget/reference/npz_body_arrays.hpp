#pragma once
/// Per-body world trajectories that go into a BeyondMimic-style NPZ beside the joint-space
/// reference (design.md §5). The reference writer does not run forward kinematics itself (the
/// formats layer knows no robot model): the caller computes these arrays with the robot model and
/// hands them in. The NPZ reader fills them back when the file has them.
///
/// Frames and units: W = world, Z up. Positions [m], linear velocities [m/s], angular velocities
/// [rad/s] in W, all of the body (link) frame origin. Frame k is at t = k / fps of the Reference.

#include <string>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

struct NpzBodyArrays {
  /// B link names. By convention body 0 is the root link (as in Isaac Lab / BeyondMimic exports);
  /// the NPZ reader uses it for the root pose only when the file has no root_pos_w/root_quat_w.
  std::vector<std::string> body_names;
  std::vector<Mat3X> p_W_body;             ///< [body] 3 x T body origin positions [m]
  std::vector<std::vector<Quat>> q_W_body; ///< [body][frame] body orientations (unit)
  /// [body] 3 x T; either empty (key omitted from the NPZ) or one matrix per body.
  std::vector<Mat3X> v_W_body;             ///< linear velocity of the body origin [m/s]
  std::vector<Mat3X> w_W_body;             ///< angular velocity [rad/s]
  /// Column order of joint_pos / joint_vel in the NPZ (npz_layout.hpp); empty = the Reference's
  /// own order. Must be a permutation of the Reference's joint names. The reader fills in the
  /// file's order.
  std::vector<std::string> joint_order;

  int num_bodies() const { return static_cast<int>(body_names.size()); }
  bool empty() const { return body_names.empty(); }
};

}  // namespace rt
