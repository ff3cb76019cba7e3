#pragma once
/// Marker trajectories taken from a decoded C3D file: the input of the marker-set profiles.
/// Positions are in metres in the file's own axes (no up-axis rotation yet); validity follows
/// the file's residual mask.

#include <string>
#include <string_view>
#include <vector>

#include "formats/c3d/c3d_file.hpp"
#include "retarget/core/types.hpp"
#include "retarget/motion/human_motion.hpp"

namespace rt {

struct MarkerTrajectory {
  std::string label;  ///< label as stored in POINT:LABELS (may carry a subject prefix)
  std::string name;   ///< normalised name (normalise_marker_name): what profiles match against
  int point_index = -1;  ///< index of the point in the C3D file
  Mat3X p_F;          ///< [m] 3 x num_frames in the file frame F; the nearest valid sample where invalid
  /// Measured where the file has a valid sample, Interpolated where a rigid-cluster fill
  /// reconstructed it (fill_from_rigid_cluster), Missing otherwise.
  std::vector<SampleState> state;

  bool valid(int frame) const { return state[static_cast<std::size_t>(frame)] != SampleState::Missing; }
};

struct MarkerTrajectories {
  int num_frames = 0;
  std::vector<MarkerTrajectory> markers;
  /// Samples marked valid in the file but farther than kMaxMarkerDistance_m from the origin
  /// (corrupt data); they are treated as missing.
  int implausible_samples = 0;

  /// Index of the marker with this normalised name, or -1.
  int find(std::string_view name) const;
  const MarkerTrajectory* get(std::string_view name) const {
    const int i = find(name);
    return i < 0 ? nullptr : &markers[static_cast<std::size_t>(i)];
  }
};

/// [m] Valid samples farther from the origin than this are treated as corrupt.
inline constexpr double kMaxMarkerDistance_m = 1e4;

/// Normalised marker name: the subject prefix ("Matt:RASI", "ANTO_M:LASI") removed, surrounding
/// blanks trimmed, upper case. "" for an empty label.
std::string normalise_marker_name(std::string_view label);

/// Marker trajectories of every point of kind Marker (model outputs such as joint angles are
/// left out), scaled by `metres_per_unit`. Unlabeled points are kept with an empty name.
/// Invalid samples hold the nearest valid sample of the same marker (0 if it has none), so that
/// arithmetic on them stays finite; `state` says which samples are real.
MarkerTrajectories marker_trajectories(const c3d::C3dFile& file, double metres_per_unit);

}  // namespace rt
