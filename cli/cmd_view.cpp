// retarget view: a reference as one self-contained HTML page (the motion viewer), and the shared
// helpers that `convert --view` and `inspect --view` use.

#include "cli/view_page.hpp"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "cli/numeric_option.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/label_contacts.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt::cli {

namespace {

struct ViewOptions {
  std::string reference;
  std::string robot;
  std::string output;
  std::vector<std::string> package_paths;
  double fps = 0;
  std::string joint_order;
  ViewerCliOptions viewer;
};

}  // namespace

void add_viewer_options(CLI::App& app, ViewerCliOptions& o, const std::string& group) {
  app.add_flag("--collision-meshes", o.collision_meshes,
               "Viewer: draw the URDF collision geometry instead of the visual meshes")
      ->group(group);
  app.add_option("--max-triangles", o.max_triangles,
                 "Viewer: triangle budget of the robot's meshes (decimated by vertex clustering)")
      ->default_val(ViewerOptions{}.max_triangles)
      ->check(bounded(100, 2000000, "triangles"))
      ->group(group);
  app.add_option("--view-fps", o.max_fps,
                 "Viewer: highest frame rate of the page [Hz]; a faster reference keeps every n-th frame (page size)")
      ->default_val(ViewerOptions{}.max_fps)
      ->check(bounded(1, 1000, "Hz"))
      ->group(group);
}

ViewerOptions viewer_options(const ViewerCliOptions& o) {
  ViewerOptions v;
  v.collision_meshes = o.collision_meshes;
  v.max_triangles = o.max_triangles;
  v.max_fps = o.max_fps;
  if (const char* dir = std::getenv("RETARGET_THREE_JS_DIR"); dir != nullptr && *dir != '\0') v.three_js_dir = dir;
  return v;
}

std::string view_page_path(const std::string& reference_path) {
  std::filesystem::path p(reference_path);
  p.replace_extension(".html");
  return p.string();
}

void write_view_page(const ViewerScene& scene, const ViewerOptions& options, const std::string& path) {
  const std::string html = viewer_page_html(scene, options);
  write_file_atomic(path, html);
  const std::string what = scene.mode == "robot" ? std::string("standing pose") : format("%d frames", scene.num_frames);
  std::cout << format("  view        %s (%s, %d triangles, %.1f MB)\n", path.c_str(), what.c_str(), scene.num_triangles(),
                      html.size() / 1e6);
  for (const std::string& n : scene.notes) std::cerr << path << ": note: " << n << "\n";
}

Command setup_view(CLI::App& parent) {
  auto v = std::make_shared<ViewOptions>();
  CLI::App* app = parent.add_subcommand(
      "view", "Write a reference as one self-contained HTML page: the robot animated in 3-D, with contacts, "
              "COM/ZMP and support polygon (three.js from Debian's libjs-three, inlined; opens offline)");
  app->add_option("reference", v->reference, "Reference: our CSV (+ meta.json beside it) or NPZ, or a plain Unitree-layout CSV")
      ->required();
  app->add_option("--robot", v->robot, "Robot: a name in robots/, a folder or a robot.yaml")->default_val("humanoid25");
  app->add_option("-o,--output", v->output, "The HTML page to write (default: the reference's path with .html)");
  app->add_option("--fps", v->fps, "Frame rate [Hz] of a plain CSV without meta.json")
      ->check(bounded(kMinFrameRate_hz, kMaxFrameRate_hz, "Hz"));
  app->add_option("--joint-order", v->joint_order,
                  "Joint order of an NPZ without joint_names: an MJCF (.xml) or a YAML list of joint names");
  add_viewer_options(*app, v->viewer, "Viewer");
  app->add_option("--package-path", v->package_paths, "Extra root folder for package:// URIs (repeatable)");
  app->footer(
      "The page shows the robot's meshes posed by the reference, play/pause, a time scrubber, playback speed, the "
      "contact timeline (feet green in contact), the kinematic COM and, when the reference has them (meta.json / "
      "NPZ com_pos_w, zmp_w), the planned COM and ZMP with the support polygon on the floor.\n"
      "Exit status: 0 written, 2 bad input (or libjs-three not installed).");
  return {app, [v, app] {
            if (app->count("--robot") == 0) std::cerr << "robot: " << v->robot << " (default; pass --robot)\n";
            const auto model = RobotModel::load(v->robot, v->package_paths);
            Reference ref = read_reference_for(*model, v->reference, v->fps, v->joint_order);
            const ViewerOptions options = viewer_options(v->viewer);
            bool labelled = false;
            if (!ref.has_contacts()) {
              // As `validate` does: the schedule from the reference's own foot heights and speeds.
              RobotData data(*model);
              const ReferenceRobotMap map(*model, ref, v->reference);
              Diagnostics ignored;
              ref.contact = label_robot_contacts(*model, data, map.q_all(ref), ref.fps, LabelContactsOptions{}, ignored,
                                                 v->reference)
                                .in_contact;
              labelled = true;
            }
            ViewerScene scene = motion_scene(*model, ref, v->reference, options);
            if (labelled)
              scene.notes.push_back("no contact schedule in the file: contacts labelled from the foot heights and speeds");
            const std::string out = v->output.empty() ? view_page_path(v->reference) : v->output;
            std::cout << format("%s on %s: %d frames at %g Hz (%.2f s)\n", v->reference.c_str(), model->name().c_str(),
                                ref.num_frames(), ref.fps, ref.duration_s());
            write_view_page(scene, options, out);
            return kExitOk;
          }};
}

}  // namespace rt::cli
