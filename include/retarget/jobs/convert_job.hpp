#pragma once
/// The `convert` job: one clip in, one robot reference out (design.md §1): load and normalise the
/// motion, run the pass pipeline, measure quality (design.md §6) and write the requested formats
/// plus meta.json atomically. The CLI and the batch workers call this; it never prints.

#include <optional>
#include <string>
#include <vector>

#include "retarget/motion/load_motion.hpp"
#include "retarget/passes/quality.hpp"
#include "retarget/pipeline/pipeline.hpp"
#include "retarget/reference/reference_io.hpp"

namespace rt {

struct ConvertRequest {
  std::string clip_path;
  std::string output;                  ///< output stem, file (.csv/.npz) or folder; "" = out/<clip stem>
  std::vector<ReferenceFormat> formats{ReferenceFormat::Csv};
  /// NPZ body/joint order (npz_layout.hpp: urdf, mjcf:FILE, names:FILE); "" = the robot's
  /// robot.yaml `npz_layout` (default urdf). Only read when the formats include npz.
  std::string npz_layout;
  double fps = 30.0;                   ///< [Hz] output rate (the resample pass's `fps`)
  double time_scale = 1.0;             ///< the retime pass's `time_scale` (> 1 slows the clip)
  double max_joint_speed = 0;          ///< [rad/s] the refine pass's `max_joint_speed` (0: the URDF limits only)
  std::string passes;                  ///< pipeline spec; "" = the default pipeline
  std::vector<std::string> disabled_passes;  ///< --no-<pass>
  std::vector<std::string> enabled_passes;   ///< --<pass> for a pass not in the default pipeline
  MotionLoadOptions motion;
  bool write_outputs = true;           ///< false: run and measure only (benchmarks, tests)
  /// Called before each pass (Pipeline::PassStarted); the CLI's progress line. Not hashed.
  Pipeline::PassStarted on_pass;
};

struct ConvertResult {
  Clip clip;
  std::string pipeline;                ///< the spec that ran, with all options
  std::vector<PassRecord> passes;
  QualityMetrics quality;
  std::string output_stem;
  std::vector<std::string> written;    ///< files written, meta.json last
  double load_ms = 0, total_ms = 0;
};

/// The formats to write for `-o OUTPUT` and `--format` (nullopt when not given): an OUTPUT ending
/// in .csv or .npz selects that format when no --format is given and must be one of the --format
/// list when one is; any other extension on OUTPUT is an InputError ("-o x.pkl" is not silently
/// written as x.pkl.csv). A folder (existing, or ending in '/') or a stem without an extension
/// takes the --format list (default csv).
std::vector<ReferenceFormat> output_formats_for(const std::string& output,
                                                const std::optional<std::vector<ReferenceFormat>>& formats);

/// Output stem for a request ("out/walk" for clip "mocap/walk.bvh" and no -o).
std::string output_stem_for(const ConvertRequest& request);

/// SHA-256 of everything in `request` that determines the outputs' content: the pipeline spec with
/// every option (as run_convert builds it), the formats, the motion load options (the profile by
/// its content) and the tool version; not the clip, the output location or write_outputs.
/// Recorded in meta.json as `options_sha256`; `retarget batch` compares it to decide whether a
/// finished clip is up to date. InputError when the pipeline spec or the profile is bad.
std::string convert_options_sha256(const ConvertRequest& request);

/// Runs the job for an already loaded robot. Throws InputError for bad input.
ConvertResult run_convert(const ConvertRequest& request, const RobotModel& model);

}  // namespace rt
