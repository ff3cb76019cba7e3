#pragma once
/// The pass pipeline: an ordered list of passes built from a textual spec, run with timing and
/// per-pass statistics (design.md §2, style anchors: Halide's lower(), MLIR's PassManager).
///
/// Spec syntax: comma-separated pass names, each optionally followed by options in braces:
///   `scale,ik{max_iterations=80},label-contacts,flat-contact,refine,ground,resample{fps=50}`

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "retarget/pipeline/pass.hpp"

namespace rt {

/// Registry entry: how to make a pass by name.
struct PassInfo {
  std::string name;
  std::string description;
  bool in_default_pipeline = true;
  std::function<std::unique_ptr<Pass>()> make;
};

using PassRegistry = std::vector<PassInfo>;  ///< in default pipeline order

/// Registry entry by name, or nullptr.
const PassInfo* find_pass(const PassRegistry& registry, const std::string& name);

/// Record of one pass run.
struct PassRecord {
  std::string name;
  std::string options;      ///< "k=v,..." as run
  double time_ms = 0;
  Statistics statistics;
};

class Pipeline {
 public:
  /// Parses a spec (InputError for unknown passes / options, naming the offending part).
  static Pipeline parse(const std::string& spec, const PassRegistry& registry);
  /// The registry's default pipeline, minus the passes named in `disabled` (each must exist).
  static Pipeline default_pipeline(const PassRegistry& registry, const std::vector<std::string>& disabled = {},
                                   const std::vector<std::string>& enabled = {});

  void add(std::unique_ptr<Pass> pass) { passes_.push_back(std::move(pass)); }
  /// Sets an option on every pass that has it; returns how many passes took it.
  int set_option_everywhere(const std::string& option, const std::string& value);
  Pass* find(const std::string& name);
  std::vector<std::string> names() const;
  /// "name{options},..." of what will run.
  std::string to_string() const;

  /// Runs every pass in order on `clip`; returns one record per pass.
  std::vector<PassRecord> run(Clip& clip, const RobotModel* model, RobotData* data) const;
  /// Called before each pass with its index, the number of passes and its name (progress lines).
  using PassStarted = std::function<void(int index, int count, const std::string& name)>;
  std::vector<PassRecord> run(Clip& clip, const RobotModel* model, RobotData* data, const PassStarted& on_pass) const;

 private:
  std::vector<std::unique_ptr<Pass>> passes_;
};

}  // namespace rt
