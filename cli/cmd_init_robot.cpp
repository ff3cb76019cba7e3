// retarget init-robot: writes a robot.yaml guessed from a humanoid URDF (robot_guess.hpp), then
// loads it and prints what was guessed, the derived soles, the sanity checks and the standing hold.

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/single_support_reach.hpp"
#include "retarget/model/robot_checks.hpp"
#include "retarget/model/robot_guess.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/standing_hold.hpp"

namespace rt::cli {

namespace {

struct InitRobotCliOptions {
  InitRobotOptions guess;
  std::string out_dir;
  bool force = false;
};

int run_init_robot(InitRobotCliOptions o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(o.guess.urdf_path, ec)) throw InputError(o.guess.urdf_path, "URDF not found");
  const std::string yaml_path = (fs::path(o.out_dir) / "robot.yaml").string();
  if (fs::exists(yaml_path, ec) && !o.force) throw InputError(yaml_path, "exists (pass --force to replace it)");
  const InitRobotResult r = guess_robot_config(o.guess);
  fs::create_directories(o.out_dir, ec);
  if (ec) throw InputError(o.out_dir, "cannot create the folder: " + ec.message());
  write_file_atomic(yaml_path, r.yaml);

  std::cout << "wrote " << yaml_path << "\nguessed:\n";
  for (const std::string& line : r.report) std::cout << "  " << line << "\n";
  // Load what was written, as every other command will.
  const auto model = RobotModel::load(load_robot_config(yaml_path));
  const char* side[2] = {"left ", "right"};
  for (int s = 0; s < 2; ++s) {
    const Sole& sole = model->soles()[static_cast<std::size_t>(s)];
    std::cout << format("  sole %s    %.3f x %.3f m on link %s, centre (%.3f, %.3f, %.3f) in the link frame\n", side[s],
                        sole.size_m.x(), sole.size_m.y(), model->links()[static_cast<std::size_t>(sole.link)].name.c_str(),
                        sole.p_L_center.x(), sole.p_L_center.y(), sole.p_L_center.z());
  }
  std::cout << format("  standing      root height %.3f m, COM height %.3f m\n", model->standing_q()[2],
                      model->standing_com_height_m());
  const StandingHoldResult hold = simulate_standing_hold(*model);
  std::cout << "  standing hold " << (hold.fell ? "falls: " + hold.failure : std::string("stands")) << "\n";
  // Static single support: can the COM be brought over each sole with the other foot lifted?
  const auto reach = single_support_reach(*model);
  std::cout << format("  one foot      COM over the left sole: %s; over the right sole: %s (IK, joint limits)\n",
                      describe_reach(reach[0]).c_str(), describe_reach(reach[1]).c_str());
  Diagnostics findings = model->diagnostics();
  findings.append(check_robot(*model));
  findings.append(check_single_support(*model, reach));
  std::cout << format("  checks        %zu warning(s)\n", findings.warning_count());
  for (const Diagnostic& d : findings.items()) std::cout << "    " << d.to_string() << "\n";
  std::cout << "next: retarget inspect " << o.out_dir << "; retarget convert CLIP --robot " << o.out_dir << " --check\n";
  return kExitOk;
}

}  // namespace

Command setup_init_robot(CLI::App& parent) {
  auto opts = std::make_shared<InitRobotCliOptions>();
  CLI::App* app = parent.add_subcommand("init-robot", "Write a robot.yaml for a humanoid URDF, guessed from its kinematic tree");
  app->add_option("urdf", opts->guess.urdf_path, "The robot's URDF")->required();
  app->add_option("-o,--output", opts->out_dir, "Folder to write robot.yaml into (created)")->required();
  app->add_option("--srdf", opts->guess.srdf_path, "SRDF whose half_sitting (or standing, home, ...) group state is the standing pose");
  app->add_option("--name", opts->guess.name, "Robot name (default: the URDF's)");
  app->add_option("--package-path", opts->guess.package_paths,
                  "Root folder for package:// URIs (repeatable; default: the folders above the URDF when needed)");
  app->add_option("--knee-bend", opts->guess.knee_bend_rad, "Knee flexion of the guessed standing pose [rad] (default 0.35)")
      ->check(CLI::Range(0.0, 1.5));
  app->add_flag("--force", opts->force, "Replace an existing robot.yaml");
  return {app, [opts] { return run_init_robot(*opts); }};
}

}  // namespace rt::cli
