#pragma once
// Command-line options of the dynamics check shared by `validate` and `convert --check`.

#include <CLI/CLI.hpp>

#include <string>

#include "retarget/sim/dynamics_check.hpp"

namespace rt::cli {

struct CheckCliOptions {
  std::string controller = "walking";
  double mass_scale = 1.0;
  double floor_friction = 0;
  bool no_dynamic_mapping = false;
  bool no_trunk_mapping = false;
};

/// Adds --controller, --mass-scale, --floor-friction, --no-dynamic-mapping, --no-trunk-mapping.
void add_check_options(CLI::App* app, CheckCliOptions& o);
/// Writes them into check options (already holding the robot's defaults).
void apply_check_options(const CheckCliOptions& o, DynamicsCheckOptions& check);

}  // namespace rt::cli
