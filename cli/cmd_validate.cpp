// retarget validate: the dynamics check of any reference (ours or another tool's).

#include <CLI/CLI.hpp>

#include <iostream>

#include "retarget/core/strings.hpp"

#include "cli/check_options.hpp"
#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "cli/numeric_option.hpp"
#include "cli/print_check.hpp"
#include "cli/progress_line.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt::cli {

namespace {

struct ValidateOptions {
  std::string reference;
  std::string robot;
  std::vector<std::string> package_paths;
  double fps = 0;
  std::string joint_order;
  std::string report_dir;
  bool json = false;
  CheckCliOptions check;
  bool find_speed = false;
};

}  // namespace

Command setup_validate(CLI::App& parent) {
  auto o = std::make_shared<ValidateOptions>();
  CLI::App* app = parent.add_subcommand(
      "validate", "Simulate a reference through the balance and tracking controllers and report balance violations");
  app->add_option("reference", o->reference, "Reference: our CSV (+ meta.json) or NPZ, or a plain Unitree-layout CSV")->required();
  app->add_option("--robot", o->robot, "Robot: a name in robots/, a folder or a robot.yaml")->default_val("humanoid25");
  app->add_option("--fps", o->fps, "Frame rate [Hz] of a plain CSV without meta.json")
      ->check(bounded(kMinFrameRate_hz, kMaxFrameRate_hz, "Hz"));
  app->add_option("--joint-order", o->joint_order,
                  "Joint order of an NPZ without joint_names: an MJCF (.xml) or a YAML list of joint names");
  app->add_option("--report", o->report_dir, "Write report.json and SVG plots into this folder");
  app->add_flag("--json", o->json, "Print the report as JSON instead of the text summary");
  add_check_options(app, o->check);
  app->add_flag("--find-speed", o->find_speed,
                "Search for the fastest playback (2x-0.25x) at which the check passes: bisection towards faster when 1x "
                "passes; otherwise a scan from 1x towards 0.25x, then bisection (a slower walk may still fail: its COM must "
                "come over each stance foot)");
  app->add_option("--package-path", o->package_paths, "Extra root folder for package:// URIs (repeatable)");
  app->footer("Exit status: 0 the check passed, 1 it failed (fall or unmet contact), 2 bad input.");
  return {app, [o, app] {
            if (app->count("--robot") == 0) std::cerr << "robot: " << o->robot << " (default; pass --robot)\n";
            const auto model = RobotModel::load(o->robot, o->package_paths);
            ValidateRequest request;
            request.reference_path = o->reference;
            request.fps = o->fps;
            request.joint_order_path = o->joint_order;
            request.check = default_check_options(*model);
            apply_check_options(o->check, request.check);
            if (o->find_speed) {
              const Reference ref = read_reference_for(*model, o->reference, o->fps, o->joint_order);
              ProgressLine searching;  // one check per trial speed: the ETA is the current trial's
              request.check.progress = simulation_progress(searching, "speed search on " + base_name(o->reference) + ", trial");
              const SpeedSearchResult s = find_feasible_speed(ref, *model, request);
              searching.stop();
              std::cout << format("%s on %s: ", o->reference.c_str(), model->name().c_str());
              if (!s.feasible)
                std::cout << format("fails at every speed tried down to %.2fx\n", 1.0 / SpeedSearchOptions{}.max_time_scale);
              else
                std::cout << format("passes at %.2fx speed (time scale %.3f)%s\n", s.speed, s.time_scale,
                                    s.passes_at_1x ? "" : "; fails at 1x");
              std::cout << "  trials     ";
              for (const auto& [S, ok] : s.trials) std::cout << format(" %.2fx:%s", 1.0 / S, ok ? "pass" : "fail");
              std::cout << "\n";
              return s.passes_at_1x ? kExitOk : kExitCheckFailed;
            }
            ProgressLine progress;
            progress.set("checking " + base_name(o->reference) + ": starting");
            request.check.progress = simulation_progress(progress, "checking " + base_name(o->reference));
            const ValidateResult r = run_validate(request, *model);
            progress.stop();
            return report_check(*model, r, request.check, o->reference, o->report_dir, o->json);
          }};
}

}  // namespace rt::cli
