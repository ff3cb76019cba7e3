#pragma once
/// User marker maps: a small YAML file (`--marker-map FILE.yaml`, MotionLoadOptions::profile_path)
/// telling the C3D reader which markers make up each canonical landmark, for marker sets the
/// built-in profiles do not know or for unlabeled files. Format:
///
///   name: my_lab            # optional; reported as the profile name
///   base: none              # optional: "none" (default) or "auto": start from the built-in
///                           #   profile that recognises the file; entries below override it
///   landmarks:              # landmark name -> one marker, or a list whose mean is taken
///     pelvis: [LHJC, RHJC]
///     left_knee: [LKNE, LKNM]
///     left_toe: LTOE
///     head: ["#1", "#2", "#3"]   # unlabeled points by 1-based point number
///
/// Landmark names are those of landmark_name() ("left_knee"); marker names are matched after
/// normalise_marker_name (subject prefix removed, case-insensitive). A landmark whose markers are
/// not all valid in a frame is missing in that frame. Unknown keys, unknown landmarks and markers
/// absent from the file are errors naming the file, line and key path.

#include <string>
#include <vector>

#include "retarget/core/yaml_view.hpp"
#include "retarget/motion/landmarks.hpp"

namespace rt {

struct MarkerMapEntry {
  Landmark landmark = Landmark::Pelvis;
  std::vector<std::string> markers;  ///< normalised marker names or "#<point number>"
  std::string location;              ///< "file:line: landmarks.left_knee" for errors
};

struct MarkerMap {
  std::string path;
  std::string name;            ///< "" -> the file's base name
  bool start_from_builtin = false;  ///< base: auto
  std::vector<MarkerMapEntry> entries;
};

MarkerMap parse_marker_map(const YamlView& root);
MarkerMap load_marker_map(const std::string& path);

}  // namespace rt
