#include "cli/check_options.hpp"

#include "cli/numeric_option.hpp"

namespace rt::cli {

void add_check_options(CLI::App* app, CheckCliOptions& o) {
  app->add_option("--controller", o.controller,
                  "Controller of the check: 'walking' (default: whole-clip COM/ZMP plan, capture-point balance, "
                  "foothold adjustment) or 'paper' (the paper's LQR balance and COM re-planning, for slow motion and ablations)")
      ->check(CLI::IsMember({"walking", "paper"}));
  app->add_option("--mass-scale", o.mass_scale,
                  "Robustness: scale every simulated link's mass and inertia (the controller keeps the nominal model)")
      ->check(bounded(0.5, 2.0, ""));
  app->add_option("--floor-friction", o.floor_friction,
                  "Robustness: sliding friction coefficient of the simulated floor (default: robot.yaml simulation.friction)")
      ->check(bounded(0.1, 2.0, ""));
  app->add_flag("--no-dynamic-mapping", o.no_dynamic_mapping, "Turn off online COM re-planning (ablation)");
  app->add_flag("--no-trunk-mapping", o.no_trunk_mapping, "Turn off trunk mapping on new contacts (ablation)");
}

void apply_check_options(const CheckCliOptions& o, DynamicsCheckOptions& check) {
  check.controller = o.controller == "paper" ? CheckControllerKind::Paper : CheckControllerKind::Walking;
  check.mass_scale = o.mass_scale;
  check.floor_friction = o.floor_friction;
  check.dynamic_mapping = !o.no_dynamic_mapping;
  check.trunk_mapping = !o.no_trunk_mapping;
}

}  // namespace rt::cli
