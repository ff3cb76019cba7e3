#pragma once
/// A pass: one small transformation of a Clip with a name, a description, a documented options
/// table and statistics (style: MLIR/LLVM passes, design.md §2). Passes hold no state between
/// runs, so one pipeline can process clips one after another, and pipelines in separate processes
/// can run in parallel.

#include <memory>
#include <string>

#include "retarget/pipeline/clip.hpp"
#include "retarget/pipeline/options.hpp"
#include "retarget/pipeline/statistics.hpp"

namespace rt {

class RobotModel;
class RobotData;

/// What a pass may use besides the clip.
struct PassContext {
  const RobotModel* robot_model = nullptr;  ///< the target robot (required by robot passes)
  RobotData* robot_data = nullptr;          ///< scratch workspace for this pipeline run
  Statistics& statistics;                   ///< the running pass's statistics
  Diagnostics& diagnostics;                 ///< warnings and notes (also in the clip)

  const RobotModel& model() const;
  RobotData& data() const;
};

class Pass {
 public:
  virtual ~Pass() = default;
  /// Registry name used by --passes / --no-<name> ("label-contacts").
  virtual std::string name() const = 0;
  virtual std::string description() const = 0;
  /// The options table, bound to this pass's options struct.
  virtual OptionTable& options() = 0;
  /// Runs on the clip. Throws InputError for bad input, InternalError for bugs.
  virtual void run(Clip& clip, PassContext& context) = 0;
};

}  // namespace rt
