#include "cli/pass_flags.hpp"

#include "retarget/passes/registry.hpp"

namespace rt::cli {

void add_pass_flags(CLI::App* app, std::vector<std::string>* enabled, std::vector<std::string>* disabled) {
  for (const PassInfo& info : builtin_passes()) {
    const std::string name = info.name;
    if (info.in_default_pipeline) {
      app->add_flag_callback("--no-" + name, [disabled, name] { disabled->push_back(name); }, "Skip the " + name + " pass")
          ->group("Passes");
      app->add_flag_callback("--" + name, [] {}, "Run the " + name + " pass (it runs by default)")->group("");
    } else {
      app->add_flag_callback("--" + name, [enabled, name] { enabled->push_back(name); },
                             "Also run the " + name + " pass (not in the default pipeline)")
          ->group("Passes");
    }
  }
}

}  // namespace rt::cli
