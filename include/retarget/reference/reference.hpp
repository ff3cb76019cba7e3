#pragma once
/// Reference: a robot reference trajectory, the product of `convert` and the input of `validate`
/// (design.md §5). In memory it mirrors the CSV + meta.json pair: root pose and joint angles per
/// frame in the export (column) order, plus what the compiler knows besides (contact schedule,
/// re-planned COM, predicted COP, provenance and quality metrics).
///
/// Frames: W = world, Z up, floor at z = 0. Frame k is at t = k / fps.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

struct Reference {
  std::string robot_name;                 ///< robot.yaml `name` (empty when unknown, e.g. a plain CSV)
  double fps = 0;                         ///< [Hz]
  std::vector<std::string> joint_names;   ///< column order of joint_pos
  Mat3X root_pos_W;                       ///< [m] root link origin, 3 x T
  std::vector<Quat> root_quat_W;          ///< root link orientation, T (unit)
  MatX joint_pos;                         ///< [rad] (or m), joints x T, rows in joint_names order

  /// Contact schedule: per foot (0 left, 1 right) per frame, 1 = in contact. Empty when unknown
  /// (e.g. a plain third-party CSV); `validate` then labels contacts from the kinematics.
  std::array<std::vector<std::uint8_t>, 2> contact;
  /// Re-planned COM (3 x T) and predicted COP (2 x T) from the com-replan pass; empty if absent.
  Mat3X com_W;
  Eigen::Matrix2Xd cop_W;

  /// Everything else of meta.json as a JSON object text (provenance: tool version, source file and
  /// hash, URDF hash, passes with options; quality metrics). Readers keep unknown keys here and
  /// writers merge it back, so a read-write round trip loses nothing.
  std::string extra_meta_json = "{}";

  int num_frames() const { return static_cast<int>(root_pos_W.cols()); }
  double duration_s() const { return num_frames() > 1 ? (num_frames() - 1) / fps : 0.0; }
  bool has_contacts() const { return !contact[0].empty(); }
};

}  // namespace rt
