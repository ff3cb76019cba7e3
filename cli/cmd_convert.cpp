// retarget convert: one clip in, one robot reference out, with a summary of what was changed.

#include <CLI/CLI.hpp>

#include <iostream>
#include <map>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "cli/numeric_option.hpp"
#include "cli/pass_flags.hpp"
#include "cli/check_options.hpp"
#include "cli/print_check.hpp"
#include "cli/progress_line.hpp"
#include "cli/view_page.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/jobs/convert_job.hpp"
#include "retarget/jobs/validate_job.hpp"
#include "retarget/motion/asf/asf_motion.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/registry.hpp"

namespace rt::cli {

namespace {

struct ConvertOptions {
  ConvertRequest request;
  std::string robot;
  std::vector<std::string> package_paths;
  std::string formats = "csv";
  std::string source_units, up_axis;
  double source_fps = 0;
  double time_scale = 1.0;
  bool keep_tpose = false;
  bool force = false;       // convert even with an implausible stature
  bool verbose = false;
  bool list_passes = false;
  bool check = false;       // run the dynamics check on the result (issue 5)
  std::string report_dir;   // write the check's report folder here (implies --check)
  CheckCliOptions check_options;
  bool view = false;        // write the motion viewer page beside the output
  ViewerCliOptions viewer;
  std::vector<std::string> disabled;  // filled from the --no-<pass> flags
  std::vector<std::string> enabled;   // filled from the --<pass> flags of passes not in the default pipeline
  // Set by `retarget batch` for its workers (hidden options): where the clip (and a manifest's
  // profile) must really be when opened, and where every output must really be written.
  std::string input_root, output_root;
  bool confine_profile = false;
};

// A pass's usual cost relative to the others, for the progress line's ETA only. Measured with -v:
// refine takes 4-27x the IK time (4x on 120 Hz clips, 26x on 30 Hz LAFAN1: IK goes by source
// frames, refine by clip time), so refine is weighted at the geometric mean, 11x; com-plan ~3x
// refine (2x on the CMU walk, 4x on LAFAN1's dance), com-replan ~0.3x, refine-ipopt ~1x,
// flat-contact and ground a few % of IK.
double pass_cost(const std::string& name) {
  static const std::map<std::string, double> kCost = {{"ik", 20},    {"flat-contact", 1}, {"refine", 220},   {"refine-ipopt", 220},
                                                      {"ground", 1}, {"com-plan", 660},  {"com-replan", 70}};
  const auto it = kCost.find(name);
  return it == kCost.end() ? 0.2 : it->second;
}

void print_pass_list() {
  for (const PassInfo& info : builtin_passes()) {
    const auto pass = info.make();
    std::cout << info.name << (info.in_default_pipeline ? "" : " (not in the default pipeline)") << "\n    "
              << info.description << "\n";
    for (const auto& e : pass->options().entries())
      std::cout << format("      %-24s %-10s %s\n", e.name.c_str(), e.get().c_str(), e.doc.c_str());
  }
}

void print_summary(const ConvertResult& r, bool verbose) {
  const HumanMotion& h = r.clip.human;
  const Reference& ref = r.clip.reference;
  const QualityMetrics& q = r.quality;
  std::cout << format("%s -> %s: %d frames at %g Hz (%.2f s)", base_name(h.source.path).c_str(),
                      ref.robot_name.c_str(), h.num_frames, h.fps, h.duration_s());
  if (ref.num_frames() > 0) std::cout << format(" -> %d frames at %g Hz", ref.num_frames(), ref.fps);
  std::cout << "\n";
  std::cout << format("  source      %s, profile %s, units %s, up axis %c, floor at %.3f m", h.source.format.c_str(),
                      h.source.profile.c_str(), h.source.units.c_str(), h.source.up_axis, h.source.floor_height_m);
  if (h.source.dropped_leading_frames) std::cout << format(", %d T-pose frame(s) dropped", h.source.dropped_leading_frames);
  std::cout << "\n";
  for (const PassRecord& p : r.passes)
    if (p.name == "scale")
      std::cout << format("  scale       leg ratio %.3f (robot leg %.3f m / human leg %.3f m)\n",
                          p.statistics.get("leg-ratio"), p.statistics.get("robot-leg-length"),
                          p.statistics.get("human-leg-length"));
  std::cout << format("  landmarks   error median %.3f m, p95 %.3f m (worst: %s)\n", q.landmark_error_median_m,
                      q.landmark_error_p95_m, q.worst_landmark.c_str());
  const std::string worst = q.worst_stance_foot < 0 ? std::string()
                                                   : format(" in the %s stance from %.2f s", q.worst_stance_foot == 0 ? "left" : "right",
                                                            q.worst_stance_start_s);
  std::cout << format("  stance      skating p95 %.4f m, max %.4f m%s (heel p95 %.4f, max %.4f m); yaw drift max %.2f deg, "
                      "tilt max %.2f deg, height max %.4f m\n",
                      q.foot_skating_p95_m, q.foot_skating_max_m, worst.c_str(), q.heel_skating_p95_m, q.heel_skating_max_m,
                      q.stance_yaw_drift_max_deg, q.stance_tilt_max_deg, q.stance_height_max_m);
  std::cout << format("  floor       lowest point %.4f m (%s at %.2f s), sole penetration %.4f m; swing clearance min %.4f m "
                      "(%d frames below %.3f m); frame 0: tilt %.2f deg, height %.4f m\n",
                      q.lowest_point_m, q.lowest_link.c_str(), q.lowest_time_s, q.penetration_max_m, q.swing_clearance_min_m,
                      q.swing_frames_low, kSwingClearance_m, q.frame0_sole_tilt_deg, q.frame0_sole_height_m);
  std::cout << format("  contacts    %d frames without a stance foot (longest %.2f s)\n", q.frames_without_stance,
                      q.longest_flight_s);
  if (r.clip.lead_in_frames > 0 || r.clip.lead_out_frames > 0)
    std::cout << format("  lead        standing lead-in %.2f s, lead-out %.2f s added by com-plan (the clip starts or ends "
                        "moving); the source's first frame is at %.2f s\n",
                        r.clip.lead_in_frames / r.clip.motion.fps, r.clip.lead_out_frames / r.clip.motion.fps,
                        r.clip.lead_in_frames / r.clip.motion.fps);
  if (q.zmp_stance_frames > 0)
    std::cout << format("  zmp         %.0f %% of %d stance frames within %.0f cm of the support (%.0f %% inside); single support "
                        "%.0f %% within (%.0f %% inside); worst %.3f m outside at %.2f s\n",
                        100 * q.zmp_near_fraction, q.zmp_stance_frames, 100 * kZmpNear_m, 100 * q.zmp_inside_fraction,
                        100 * q.zmp_single_near_fraction, 100 * q.zmp_single_inside_fraction, q.zmp_outside_max_m,
                        q.zmp_outside_time_s);
  std::cout << format("  limits      %d position violations, %d velocity violations (fastest: %s at %.2f, %.2fx its limit)\n",
                      q.position_limit_violations, q.velocity_limit_violations, q.fastest_joint.c_str(),
                      q.fastest_joint_speed, q.max_velocity_ratio);
  if (!q.torque_demand_joint.empty())
    std::cout << format("  torques     joints above the feet: %s asks %.2fx its effort limit at %.2f s; %d frames over a limit "
                        "(inverse dynamics of the frames)\n",
                        q.torque_demand_joint.c_str(), q.torque_demand_max_ratio, q.torque_demand_time_s, q.torque_demand_frames_over);
  std::cout << format("  jitter      %.1f rad/s^3 (per-frame IK: %.1f rad/s^3)\n", q.jitter_rad_s3,
                      q.jitter_per_frame_ik_rad_s3);
  std::string times;
  for (const PassRecord& p : r.passes) times += format("%s%s %.1f ms", times.empty() ? "" : ", ", p.name.c_str(), p.time_ms);
  std::cout << format("  time        load %.1f ms; %s; total %.1f ms\n", r.load_ms, times.c_str(), r.total_ms);
  if (!r.written.empty()) std::cout << "  wrote       " << join(r.written, ", ") << "\n";
  if (verbose) {
    std::cout << "\nlandmark error per landmark [m]:\n";
    for (const LandmarkErrorStat& e : q.landmark_errors)
      std::cout << format("  %-16s median %.4f  p95 %.4f\n", e.landmark.c_str(), e.median_m, e.p95_m);
    std::cout << "\npipeline: " << r.pipeline << "\n";
    for (const PassRecord& p : r.passes) {
      std::cout << format("  %-16s %9.2f ms\n", p.name.c_str(), p.time_ms);
      for (const Statistic& s : p.statistics.items())
        std::cout << format("      (S) %-28s %12.6g %-7s %s\n", s.name.c_str(), s.value, s.unit.c_str(), s.note.c_str());
    }
  }
  for (const Diagnostic& d : h.diagnostics.items()) std::cerr << d.to_string() << "\n";
  for (const Diagnostic& d : r.clip.diagnostics.items()) std::cerr << d.to_string() << "\n";
}

}  // namespace

Command setup_convert(CLI::App& parent) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* app = parent.add_subcommand("convert", "Retarget a BVH, C3D or ASF/AMC clip to a robot and write the reference");
  app->add_option("clip", o->request.clip_path, "Motion capture file (.bvh, .c3d or .amc)");
  app->add_option("--robot", o->robot, "Robot: a name in robots/, a folder or a robot.yaml")->default_val("humanoid25");
  app->add_option("-o,--output", o->request.output,
                  "Output stem, .csv/.npz file or folder (default: out/<clip name>); meta.json goes beside it");
  app->add_option("--format", o->formats, "Output formats, comma-separated: csv, npz")->default_val("csv");
  app->add_option("--npz-layout", o->request.npz_layout,
                  "NPZ body and joint order: urdf, mjcf:FILE (a simulator's MJCF order) or names:FILE "
                  "(default: the robot's robot.yaml npz_layout, else urdf)");
  app->add_option("--fps", o->request.fps, "Output frame rate [Hz]")
      ->default_val(30.0)
      ->check(bounded(kMinFrameRate_hz, kMaxOutputFrameRate_hz, "Hz"));
  app->add_option("--passes", o->request.passes,
                  "Pipeline to run instead of the default, e.g. 'scale,ik{max_iterations=80},label-contacts,resample'");
  add_pass_flags(app, &o->enabled, &o->disabled);
  app->add_flag("--list-passes", o->list_passes, "List the passes with their options and defaults, then exit");
  app->add_option("--source-units", o->source_units, "Override the detected source units: m, cm, mm, inch, cmu or metres per unit");
  app->add_option("--source-fps", o->source_fps, "Override the source frame rate [Hz]")
      ->check(bounded(kMinFrameRate_hz, kMaxFrameRate_hz, "Hz"));
  app->add_option("--up-axis", o->up_axis, "Override the detected source up axis: x, y, z (optionally -y, ...)");
  app->add_option("--asf", o->request.motion.asf_path,
                  "ASF skeleton of an AMC clip (default: found beside it, CMU naming 01_01.amc -> 01.asf)");
  app->add_option("--skeleton-profile,--marker-map", o->request.motion.profile_path,
                  "YAML mapping landmarks to BVH joint names or C3D markers (README: Motion input)");
  app->add_flag("--force", o->force,
                "Convert even when the clip's stature is implausible (outside 0.5-2.5 m: usually wrong units)");
  app->add_flag("--keep-tpose", o->keep_tpose, "Keep a synthetic T-pose at the start instead of dropping it");
  app->add_option("--time-scale", o->time_scale, "Play the clip S times slower (S > 1) or faster (S < 1) before IK (the retime pass)")
      ->check(bounded(0.05, 20.0, ""));
  app->add_option("--max-joint-speed", o->request.max_joint_speed,
                  "Cap every joint's speed [rad/s] below its URDF limit (the refine pass's max_joint_speed; other tools "
                  "default to 3 pi = 9.42)")
      ->check(bounded(0.01, 1000.0, "rad/s"));
  app->add_option("--package-path", o->package_paths, "Extra root folder for package:// URIs (repeatable)");
  app->add_flag("-v,--verbose", o->verbose, "Print the pipeline with all options and per-pass statistics");
  app->add_flag("--check", o->check,
                "After converting, run the dynamics check on the result (as 'retarget validate'); exit 1 when it fails");
  app->add_option("--report", o->report_dir, "With --check: write report.json, report.txt and SVG plots into this folder "
                                             "(implies --check)");
  add_check_options(app, o->check_options);
  app->add_flag("--view", o->view,
                "Also write the motion viewer page <output stem>.html: the robot with the source skeleton "
                "(scaled landmarks) over it (see 'retarget view')");
  add_viewer_options(*app, o->viewer, "Viewer (with --view)");
  app->add_option("--input-root", o->input_root, "(batch workers) the clip must resolve inside this folder when opened")
      ->group("");
  app->add_flag("--confine-profile", o->confine_profile, "(batch workers) the profile is under --input-root too")->group("");
  app->add_option("--output-root", o->output_root, "(batch workers) every output must be written inside this folder")
      ->group("");
  app->footer("Exit status: 0 ok (and the check passed), 1 the check failed (outputs are written), 2 bad input.");
  return {app, [o, app] {
            if (o->list_passes) {
              print_pass_list();
              return kExitOk;
            }
            if (o->request.clip_path.empty()) throw InputError("convert", "a clip is required (retarget convert CLIP --robot ROBOT)");
            std::optional<std::vector<ReferenceFormat>> listed;
            if (app->count("--format") > 0) listed = parse_reference_formats(o->formats);
            o->request.formats = output_formats_for(o->request.output, listed);
            if (app->count("--robot") == 0) std::cerr << "robot: " << o->robot << " (default; pass --robot)\n";
            o->request.motion.allow_implausible_stature = o->force;
            o->request.disabled_passes = o->disabled;
            o->request.enabled_passes = o->enabled;
            if (!o->source_units.empty()) o->request.motion.source_units = o->source_units;
            if (o->source_fps > 0) o->request.motion.source_fps = o->source_fps;
            if (!o->up_axis.empty()) o->request.motion.up_axis = o->up_axis;
            o->request.motion.drop_tpose = !o->keep_tpose;
            o->request.time_scale = o->time_scale;
            if (o->view) require_three_js(viewer_options(o->viewer));  // fail before converting
            const auto model = RobotModel::load(o->robot, o->package_paths);
            // Checked where the files are opened (file_io.hpp), for the rest of this command.
            PathConfinement confinement;
            confinement.write_root = o->output_root;
            if (!o->input_root.empty()) {
              confinement.read_root = o->input_root;
              confinement.confined_reads.push_back(o->request.clip_path);
              if (o->confine_profile && !o->request.motion.profile_path.empty())
                confinement.confined_reads.push_back(o->request.motion.profile_path);
              if (ends_with(to_lower(o->request.clip_path), ".amc")) {
                try {
                  confinement.confined_reads.push_back(find_asf_for(o->request.clip_path, o->request.motion.asf_path));
                } catch (const InputError&) {
                  // no ASF: the loader reports it
                }
              }
            }
            const ScopedPathConfinement confined(std::move(confinement));
            ProgressLine progress;
            const std::string clip_name = base_name(o->request.clip_path);
            progress.set("converting " + clip_name + ": loading", 0.0);
            std::vector<double> cost_before;  // cumulative pass costs, filled at the first pass
            o->request.on_pass = [&progress, &cost_before, clip_name, request = &o->request](int index, int count,
                                                                                            const std::string& name) {
              if (cost_before.empty()) {  // the pipeline run_convert built, parsed again for its pass names
                const Pipeline p = request->passes.empty()
                                       ? Pipeline::default_pipeline(builtin_passes(), request->disabled_passes, request->enabled_passes)
                                       : Pipeline::parse(request->passes, builtin_passes());
                cost_before.push_back(0);
                for (const std::string& n : p.names()) cost_before.push_back(cost_before.back() + pass_cost(n));
              }
              const double total = cost_before.back();
              const bool known = static_cast<int>(cost_before.size()) == count + 1 && total > 0;
              const std::string status = format("converting %s: pass %d/%d %s", clip_name.c_str(), index + 1, count, name.c_str());
              if (known)
                progress.set(status, cost_before[static_cast<std::size_t>(index)] / total,
                             cost_before[static_cast<std::size_t>(index) + 1] / total);
              else
                progress.set(status);
            };
            const ConvertResult r = run_convert(o->request, *model);
            progress.stop();
            print_summary(r, o->verbose);
            if (o->view) {
              const ViewerOptions options = viewer_options(o->viewer);
              ViewerScene scene = motion_scene(*model, r.clip.reference, r.output_stem, options);
              scene.title = model->name() + ": " + clip_name;
              scene.skeleton = skeleton_points(r.clip.targets.tracks, r.clip.motion.fps, scene);
              write_view_page(scene, options, r.output_stem + ".html");
            }
            if (!o->check && o->report_dir.empty()) return kExitOk;
            ValidateRequest check;
            check.reference_path = r.written.empty() ? r.output_stem : r.written.front();
            check.check = default_check_options(*model);
            apply_check_options(o->check_options, check.check);
            std::cout << "\n";
            ProgressLine checking;
            checking.set("checking " + clip_name + ": starting");
            check.check.progress = simulation_progress(checking, "checking " + clip_name);
            const ValidateResult v = validate_reference(r.clip.reference, *model, check);
            checking.stop();
            return report_check(*model, v, check.check, check.reference_path, o->report_dir, false);
          }};
}

}  // namespace rt::cli
