#pragma once
/// A subcommand: each lives in its own cli/cmd_<name>.cpp with a `setup_<name>(CLI::App&)` that
/// registers its options and returns the function that runs it after parsing.

#include <functional>

namespace CLI {
class App;
}

namespace rt::cli {

struct Command {
  CLI::App* app = nullptr;   ///< the subcommand's parser
  std::function<int()> run;  ///< runs the command; returns the exit status
};

Command setup_inspect(CLI::App& parent);
Command setup_convert(CLI::App& parent);
Command setup_validate(CLI::App& parent);
Command setup_batch(CLI::App& parent);
Command setup_merge_summaries(CLI::App& parent);
Command setup_init_robot(CLI::App& parent);
Command setup_view(CLI::App& parent);

}  // namespace rt::cli
