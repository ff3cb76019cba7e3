#pragma once
/// HumanMotion: the neutral form of any motion-capture input (design.md §3.1).
///
/// World frame W of a HumanMotion: metres, Z up, the estimated floor at z = 0, and (unless the
/// caller disabled alignment) the subject's pelvis above the origin facing +X at frame 0.
/// Time: frame k is at t = k / fps seconds.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "retarget/core/diagnostics.hpp"
#include "retarget/core/types.hpp"
#include "retarget/motion/landmarks.hpp"

namespace rt {

/// Per-sample validity codes of a LandmarkTrack.
enum class SampleState : std::uint8_t {
  Missing = 0,       ///< no data (gap longer than the fill limit, or occluded at an end);
                     ///< p_W holds the nearest valid sample so arithmetic stays finite
  Measured = 1,      ///< from the source data
  Interpolated = 2,  ///< gap filled by interpolation (within the fill limit)
};

/// Trajectory of one landmark.
struct LandmarkTrack {
  bool present = false;  ///< the source defines this landmark at all
  Mat3X p_W;             ///< [m] position in W, 3 x num_frames (empty when !present)
  std::vector<SampleState> state;  ///< per frame (empty when !present)

  /// Orientation of the landmark's anatomical frame in W (pelvis, chest, feet only), derived
  /// geometrically from landmark positions so that every source uses the same convention:
  /// x forward, y to the subject's left, z up when the subject stands upright.
  bool has_orientation = false;
  std::vector<Quat> R_W;  ///< per frame, unit quaternions (empty when !has_orientation)

  bool valid(int frame) const { return present && state[static_cast<std::size_t>(frame)] != SampleState::Missing; }
};

/// Where the motion came from and what normalisation did to it (printed by `retarget inspect`).
struct MotionSourceInfo {
  std::string path;
  std::string format;           ///< "bvh" or "c3d"
  std::string profile;          ///< recognised skeleton / marker-set profile name
  double file_fps = 0;          ///< [Hz] rate stated by the file
  int file_frames = 0;          ///< frames stated by / found in the file
  std::string units;            ///< detected or overridden source units: "m", "cm", "mm", "inch", "cmu"
  double metres_per_unit = 1;   ///< scale applied to source coordinates
  bool units_overridden = false;
  char up_axis = 'z';           ///< source up axis: 'x', 'y' or 'z' (sign folded into the rotation)
  bool up_axis_overridden = false;
  int dropped_leading_frames = 0;  ///< synthetic T-pose frames removed at the start
  double floor_height_m = 0;    ///< [m] floor height found in the source (before it was moved to z = 0)
  double floor_tilt_deg = 0;    ///< slope of the floor plane fitted to the feet's contacts, removed (floor_plane.hpp)
  double floor_unevenness_m = 0;  ///< spread of the contact heights about that plane
  /// Format-specific facts ("joints": "31", "markers": "55", "channels": "96", ...).
  std::map<std::string, std::string> details;
};

struct HumanMotion {
  MotionSourceInfo source;
  double fps = 0;       ///< [Hz] frame rate after overrides
  int num_frames = 0;
  /// Played this many times slower than recorded (the retime pass; 1 for a loaded clip): one second
  /// of the source is fps · time_scale frames. Speed thresholds are taken on the source timeline.
  double time_scale = 1;
  std::array<LandmarkTrack, kLandmarkCount> landmarks;
  Diagnostics diagnostics;  ///< warnings and notes produced while loading

  double duration_s() const { return num_frames > 1 ? (num_frames - 1) / fps : 0.0; }
  double time_s(int frame) const { return frame / fps; }
  const LandmarkTrack& operator[](Landmark l) const { return landmarks[static_cast<std::size_t>(index(l))]; }
  LandmarkTrack& operator[](Landmark l) { return landmarks[static_cast<std::size_t>(index(l))]; }
  bool has(Landmark l) const { return (*this)[l].present; }
};

}  // namespace rt
