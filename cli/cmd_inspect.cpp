// retarget inspect: prints what retarget understands of a robot (and, once motion input lands, of
// a clip).

#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "cli/numeric_option.hpp"
#include "cli/view_page.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/single_support_reach.hpp"
#include "retarget/model/robot_checks.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/standing_hold.hpp"
#include "retarget/motion/load_motion.hpp"

namespace rt::cli {

namespace {

struct InspectOptions {
  std::string target;
  std::vector<std::string> package_paths;
  MotionLoadOptions motion;
  std::string source_units, up_axis;
  double source_fps = 0;
  bool keep_tpose = false;
  std::string mjcf_path;  ///< robot: write the generated MuJoCo model here
  bool view = false;      ///< robot: write the viewer page of the standing pose
  std::string view_path;  ///< its path ("" = <robot name>.html)
  ViewerCliOptions viewer;
};

// A robot is a name, a folder or a .yaml; anything else that is a file is a motion clip.
bool is_clip(const std::string& target) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(target, ec)) return false;
  const std::string lower = to_lower(target);
  return !ends_with(lower, ".yaml") && !ends_with(lower, ".yml");
}

int inspect_clip(InspectOptions o) {
  if (!o.source_units.empty()) o.motion.source_units = o.source_units;
  if (o.source_fps > 0) o.motion.source_fps = o.source_fps;
  if (!o.up_axis.empty()) o.motion.up_axis = o.up_axis;
  o.motion.drop_tpose = !o.keep_tpose;
  MotionLoadOptions motion = o.motion;
  motion.allow_implausible_stature = true;  // show what was read; convert refuses it
  const HumanMotion m = load_motion(o.target, motion);
  const MotionSourceInfo& s = m.source;
  std::cout << "clip " << s.path << "\n";
  std::cout << format("  format        %s, profile %s\n", s.format.c_str(), s.profile.c_str());
  std::cout << format("  frames        %d used of %d in the file (%d synthetic T-pose frame(s) dropped)\n", m.num_frames,
                      s.file_frames, s.dropped_leading_frames);
  std::cout << format("  rate          %g Hz (file: %g Hz)%s; duration %.2f s\n", m.fps, s.file_fps,
                      std::abs(m.fps - s.file_fps) > 1e-9 ? " overridden" : "", m.duration_s());
  std::cout << format("  units         %s (%g m per unit)%s\n", s.units.c_str(), s.metres_per_unit,
                      s.units_overridden ? ", overridden" : ", detected");
  std::cout << format("  up axis       %c%s\n", s.up_axis, s.up_axis_overridden ? ", overridden" : ", detected");
  std::cout << format("  floor height  %.3f m in the source (moved to z = 0)\n", s.floor_height_m);
  std::cout << format("  floor tilt    %.2f deg under the feet%s, uneven by %.3f m (p90 - p10 of the contacts about the plane)\n",
                      s.floor_tilt_deg, s.floor_tilt_deg > 0 ? " (levelled)" : "", s.floor_unevenness_m);
  for (const auto& [key, value] : s.details) std::cout << format("  %-13s %s\n", key.c_str(), value.c_str());
  std::vector<std::string> found, missing;
  for (Landmark l : all_landmarks()) {
    const LandmarkTrack& t = m[l];
    if (!t.present) {
      missing.push_back(std::string(landmark_name(l)));
      continue;
    }
    int valid = 0;
    for (int f = 0; f < m.num_frames; ++f) valid += t.valid(f);
    std::string entry = std::string(landmark_name(l));
    if (valid < m.num_frames) entry += format(" (%d%% valid)", m.num_frames ? 100 * valid / m.num_frames : 0);
    if (t.has_orientation) entry += " +orientation";
    found.push_back(entry);
  }
  std::cout << "  landmarks     " << found.size() << " found: " << join(found, ", ") << "\n";
  if (!missing.empty()) std::cout << "  missing       " << join(missing, ", ") << "\n";
  for (const Diagnostic& d : m.diagnostics.items()) std::cout << "  " << d.to_string() << "\n";
  return kExitOk;
}

const char* joint_type_name(JointType t) {
  switch (t) {
    case JointType::Revolute: return "revolute";
    case JointType::Continuous: return "continuous";
    case JointType::Prismatic: return "prismatic";
    case JointType::Fixed: return "fixed";
    case JointType::Floating: return "floating";
  }
  return "?";
}

std::string limit_text(double v) { return std::isfinite(v) ? format("%8.3f", v) : std::string("       -"); }

int inspect_robot(const InspectOptions& o) {
  RobotLoadOptions load;
  load.keep_mjcf_assets = !o.mjcf_path.empty();
  const auto model = RobotModel::load(load_robot_config(o.target, o.package_paths), load);
  const RobotConfig& c = model->config();
  int fixed = 0;
  for (const Joint& j : model->joints()) fixed += j.type == JointType::Fixed;
  const VecX& q0 = model->standing_q();

  std::cout << "robot " << model->name() << "  (" << c.config_path << ")\n";
  std::cout << "  urdf          " << c.urdf_path << "\n";
  std::cout << format("  structure     %zu links, %d movable joints, %d fixed; nq %d, nv %d\n", model->links().size(),
                      model->nu(), fixed, model->nq(), model->nv());
  std::cout << format("  mass          %.2f kg\n", model->total_mass_kg());
  std::cout << format("  standing      root height %.3f m, COM height %.3f m\n", q0[2], model->standing_com_height_m());
  const char* side[2] = {"left ", "right"};
  for (int s = 0; s < 2; ++s) {
    const Sole& sole = model->soles()[static_cast<std::size_t>(s)];
    std::cout << format("  sole %s    %-24s %.3f x %.3f m, centre (%.3f, %.3f, %.3f) in the link frame\n", side[s],
                        model->links()[static_cast<std::size_t>(sole.link)].name.c_str(), sole.size_m.x(),
                        sole.size_m.y(), sole.p_L_center.x(), sole.p_L_center.y(), sole.p_L_center.z());
  }
  std::cout << "  landmarks     " << c.landmarks.size() << " mapped:";
  for (const LandmarkTarget& t : c.landmarks) std::cout << " " << landmark_name(t.landmark);
  std::cout << "\n";
  // The standing hold with robot.yaml's simulation.hold_kp / hold_kd: does the model stand at all?
  const StandingHoldResult hold = simulate_standing_hold(*model);
  std::cout << format("  standing hold %s (%.1f s joint PD at the standing pose, simulation.hold_kp %g, hold_kd %g; "
                      "COM drift %.3f m)\n",
                      hold.fell ? ("falls: " + hold.failure).c_str() : "stands", hold.simulated_s,
                      c.simulation.hold_kp, c.simulation.hold_kd, hold.max_com_drift_m);
  // Static single support: can the COM be brought over each sole with the other foot lifted?
  const auto reach = single_support_reach(*model);
  std::cout << format("  one foot      COM over the left sole: %s; over the right sole: %s (IK, joint limits)\n",
                      describe_reach(reach[0]).c_str(), describe_reach(reach[1]).c_str());
  Diagnostics findings = model->diagnostics();
  findings.append(check_robot(*model));
  findings.append(check_single_support(*model, reach));
  std::cout << format("  checks        %zu warning(s), %zu note(s)\n", findings.warning_count(),
                      findings.items().size() - findings.warning_count());
  for (const Diagnostic& d : findings.items()) std::cout << "    " << d.to_string() << "\n";
  if (!o.mjcf_path.empty()) {
    model->write_mjcf(o.mjcf_path);
    std::cout << "  wrote         " << o.mjcf_path << " (the generated MuJoCo model; its meshes beside it as mesh<k>.stl)\n";
  }
  if (o.view) {
    const ViewerOptions options = viewer_options(o.viewer);
    write_view_page(robot_scene(*model, options), options, o.view_path.empty() ? model->name() + ".html" : o.view_path);
  }
  std::cout << "\njoints (model order; csv = export column after the 7 root columns)\n";
  std::cout << "   #  csv  name                          type          lower    upper  vel-lim  effort  standing\n";
  std::vector<int> column(static_cast<std::size_t>(model->nu()), -1);
  for (std::size_t k = 0; k < model->export_joint_order().size(); ++k)
    column[static_cast<std::size_t>(model->export_joint_order()[k])] = static_cast<int>(k);
  for (int i = 0; i < model->nu(); ++i) {
    const Joint& j = model->joints()[static_cast<std::size_t>(model->movable_joints()[static_cast<std::size_t>(i)])];
    std::cout << format("  %2d  %3d  %-29s %-11s %s %s %8.2f %7.1f  %8.3f\n", i, column[static_cast<std::size_t>(i)],
                        j.name.c_str(), joint_type_name(j.type), limit_text(model->q_lower()[i]).c_str(),
                        limit_text(model->q_upper()[i]).c_str(), model->velocity_limits()[i],
                        model->effort_limits()[i], q0[7 + i]);
  }
  return kExitOk;
}

}  // namespace

Command setup_inspect(CLI::App& parent) {
  auto opts = std::make_shared<InspectOptions>();
  CLI::App* app = parent.add_subcommand(
      "inspect", "Print what retarget reads from a robot (name, folder or robot.yaml) or a motion clip (.bvh, .c3d)");
  app->add_option("target", opts->target, "Robot (a name in robots/, a folder or a robot.yaml) or a BVH/C3D clip")->required();
  app->add_option("--source-units", opts->source_units, "Clip: override the detected units (m, cm, mm, inch, cmu or metres per unit)");
  app->add_option("--source-fps", opts->source_fps, "Clip: override the frame rate [Hz]")
      ->check(bounded(kMinFrameRate_hz, kMaxFrameRate_hz, "Hz"));
  app->add_option("--up-axis", opts->up_axis, "Clip: override the detected up axis (x, y, z, -y, ...)");
  app->add_option("--skeleton-profile,--marker-map", opts->motion.profile_path, "Clip: YAML landmark map for the skeleton / markers");
  app->add_flag("--keep-tpose", opts->keep_tpose, "Clip: keep a synthetic T-pose at the start");
  app->add_option("--mjcf", opts->mjcf_path,
                  "Robot: write the generated MuJoCo model (MJCF) to this file, its meshes beside it as mesh<k>.stl");
  app->add_option("--package-path", opts->package_paths,
                  "Extra root folder for package:// URIs (repeatable; searched before robot.yaml's and ROS_PACKAGE_PATH)");
  app->add_flag("--view", opts->view,
                "Robot: write the viewer page of the standing pose with soles and landmarks (see 'retarget view')");
  app->add_option("-o,--output", opts->view_path, "Robot: the --view page (default: <robot name>.html)");
  add_viewer_options(*app, opts->viewer, "Viewer (with --view)");
  return {app, [opts] {
            const bool clip = is_clip(opts->target);
            if (!opts->view && !opts->view_path.empty()) throw InputError("-o", "names the --view page; add --view");
            if (opts->view && clip) throw InputError("--view", "shows a robot; for a clip use 'retarget convert CLIP --view'");
            if (opts->view) require_three_js(viewer_options(opts->viewer));
            return clip ? inspect_clip(*opts) : inspect_robot(*opts);
          }};
}

}  // namespace rt::cli
