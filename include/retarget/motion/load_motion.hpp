#pragma once
/// Loading any supported motion-capture file into a HumanMotion, and the options shared by all
/// readers (command-line flags --source-units, --source-fps, --up-axis, --skeleton-profile).

#include <optional>
#include <string>

#include "retarget/motion/human_motion.hpp"
#include "retarget/motion/normalize.hpp"

namespace rt {

struct MotionLoadOptions {
  /// Override of the detected source units: "m", "cm", "mm", "inch", "cmu" (CMU ASF units,
  /// 1/0.45 inch) or a number of metres per unit.
  std::optional<std::string> source_units;
  /// Override of the file's frame rate [Hz] (some CMU conversions claim 120 Hz for 60 Hz data).
  std::optional<double> source_fps;
  /// Override of the detected up axis: "x", "y", "z", optionally with a sign ("-y").
  std::optional<std::string> up_axis;
  /// User profile (YAML): BVH joint names -> landmarks, or C3D marker names -> landmarks.
  std::string profile_path;
  /// The ASF skeleton of an AMC clip (`--asf`); "" = found beside the AMC (asf_motion.hpp).
  std::string asf_path;
  /// Detect and drop a synthetic T-pose at the start (CMU MotionBuilder/Daz releases, iClone).
  bool drop_tpose = true;
  /// [s] C3D gaps up to this long are filled by interpolation; longer gaps stay Missing.
  double max_gap_s = 0.25;
  NormalizeOptions normalize;
  /// Load a clip whose estimated stature is implausible (source_checks.hpp) instead of refusing
  /// it (`--force`; `inspect` always does, to show what was read).
  bool allow_implausible_stature = false;
};

/// Metres per unit for a units name or number ("cm" -> 0.01, "0.05" -> 0.05). Throws InputError
/// for unknown names and non-positive numbers.
double metres_per_unit(const std::string& units);

/// Canonical units name for a scale if it matches a known unit ("cm" for 0.01), else the number.
std::string units_name(double metres_per_unit);

/// Parses an up-axis override ("y", "-z", "Z"): returns the axis letter ('x','y','z') and whether
/// it points down. Throws InputError otherwise.
std::pair<char, bool> parse_up_axis(const std::string& text);

/// Loads a BVH, C3D or AMC (+ its ASF) file (chosen by content, then extension). Throws InputError with a location
/// for malformed input, for sources whose skeleton / marker set cannot be recognised, and for an
/// implausible stature (wrong units; unless allow_implausible_stature). Warns when the frames
/// repeat in a regular pattern (a wrong frame rate; unless source_fps is given).
HumanMotion load_motion(const std::string& path, const MotionLoadOptions& options = {});

}  // namespace rt
