#pragma once
/// Resolution of resource references found in URDF files and robot configs:
///   package://pkg/rel/path   -> <root>/pkg/rel/path or <root>/<any>/pkg/rel/path for the first
///                               root of the search path that holds the file
///   package:///pkg/rel/path  -> /pkg/rel/path when that file exists, else as package://pkg/rel/path
///                               (an empty authority, as example-robot-data URDFs write it)
///   file:///abs/path         -> /abs/path
///   relative/path            -> <base_dir>/relative/path
///   /abs/path                -> /abs/path

#include <string>
#include <vector>

namespace rt {

struct ResolvedResource {
  std::string path;   ///< absolute, normalised path of an existing file; empty when not found
  std::string error;  ///< why it was not found (one line, for an InputError); empty on success
};

/// Resolves `uri` (see above). Never throws for a missing file: the caller adds its location.
ResolvedResource resolve_package_uri(const std::string& uri, const std::string& base_dir,
                                     const std::vector<std::string>& package_paths);

/// Splits a colon-separated path list (ROS_PACKAGE_PATH style), dropping empty entries.
std::vector<std::string> split_path_list(const std::string& list);

}  // namespace rt
