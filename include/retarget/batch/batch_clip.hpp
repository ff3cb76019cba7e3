#pragma once
/// One clip of a batch (`retarget batch`, design.md §1): where its input is, what its outputs are
/// called, and the per-clip overrides a manifest may give.

#include <cstdint>
#include <optional>
#include <string>

namespace rt {

/// Per-clip settings a manifest may give; each one, when set, replaces the batch-wide value of
/// the `convert` flag of the same name (README "Batch processing"). Paths are absolute.
struct ClipOverrides {
  std::optional<std::string> source_units;  ///< --source-units: m, cm, mm, inch, cmu or metres per unit
  std::optional<double> source_fps;         ///< --source-fps [Hz], > 0
  std::optional<double> time_scale;         ///< --time-scale, in [0.05, 20]
  std::optional<std::string> up_axis;       ///< --up-axis: x, y, z, optionally signed
  std::optional<std::string> profile;       ///< --skeleton-profile / --marker-map (absolute path)

  bool empty() const { return !source_units && !source_fps && !time_scale && !up_axis && !profile; }
};

struct BatchClip {
  std::string input;            ///< absolute, lexically normal path of the BVH/C3D file
  /// Output name relative to the output folder, without extension ("walks/walk01"): the worker
  /// writes <out>/<name>.csv (.npz), <name>.meta.json, <name>.log and <name>.report/.
  std::string output_name;
  ClipOverrides overrides;
  std::uint64_t input_bytes = 0;  ///< file size (0 when missing); the sharding weight
  std::string origin;             ///< where the clip was listed: "manifest.yaml:12", or the folder
  /// The resolved folder the input must stay within (the manifest's folder or the input folder);
  /// "" with --allow-outside. Checked again when the worker starts (a symlink may change).
  std::string input_root;
};

}  // namespace rt
