// retarget: command-line entry point. Wiring only: each subcommand is in cli/cmd_<name>.cpp.

#include <CLI/CLI.hpp>

#include <csignal>
#include <iostream>
#include <vector>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "cli/suggest.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/core/version.hpp"

int main(int argc, char** argv) {
  using namespace rt::cli;
  // A write beyond the file-size limit (ulimit -f) then fails with EFBIG, so the atomic writer
  // removes its temporary and reports the file, instead of the process dying with a stale .tmp.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"retarget: a motion retargeting compiler for humanoid robots.\n"
               "Turns human motion capture (BVH, C3D) into robot reference trajectories for a URDF robot."};
  app.set_version_flag("--version", std::string("retarget ") + rt::kVersion);
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 ok, 1 check failed, 2 bad input or usage, 3 internal error.\n"
      "Run 'retarget <command> --help' for a command's options.");

  std::vector<Command> commands = {setup_convert(app), setup_validate(app), setup_batch(app),
                                   setup_merge_summaries(app), setup_inspect(app), setup_init_robot(app), setup_view(app)};

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // A mistyped option: name it with the closest real one instead of CLI11's generic message.
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
      const std::vector<std::string> hints = unknown_option_hints(app, argc, argv);
      if (!hints.empty()) {
        std::cerr << "error: " << hints.front() << "\n";
        return kExitBadInput;
      }
    }
    // --help and --version (exit code 0): CLI11 prints them. A usage error: one line, as every
    // other error (CLI11's own printer adds a second "Run with --help" line).
    if (e.get_exit_code() == 0) return app.exit(e) == 0 ? kExitOk : kExitBadInput;
    std::string command;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App* s) { return s->parsed(); }))
      command = sub->get_name() + " ";
    std::cerr << "error: " << rt::one_line(e.what()) << " (see 'retarget " << command << "--help')\n";
    return kExitBadInput;
  }

  try {
    for (const Command& c : commands)
      if (c.app->parsed()) return c.run();
    return kExitBadInput;
  } catch (const rt::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return kExitInternal;
  }
}
