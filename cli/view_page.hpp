#pragma once
/// The viewer options and page writing shared by `view`, `convert --view` and `inspect --view`.

#include <string>

#include "retarget/report/motion_viewer.hpp"

namespace CLI {
class App;
}

namespace rt::cli {

struct ViewerCliOptions {
  bool collision_meshes = false;
  int max_triangles = ViewerOptions{}.max_triangles;
  double max_fps = ViewerOptions{}.max_fps;  ///< [Hz]
};

/// Registers --collision-meshes, --max-triangles and --view-fps in `group`.
void add_viewer_options(CLI::App& app, ViewerCliOptions& options, const std::string& group);
/// The options, with three.js from $RETARGET_THREE_JS_DIR when set (else libjs-three's folder).
ViewerOptions viewer_options(const ViewerCliOptions& options = {});

/// `out/walk.csv` -> `out/walk.html` (beside the reference).
std::string view_page_path(const std::string& reference_path);

/// Writes the page atomically and prints one "view" line (notes go to stderr).
void write_view_page(const ViewerScene& scene, const ViewerOptions& options, const std::string& path);

}  // namespace rt::cli
