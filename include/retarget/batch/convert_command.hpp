#pragma once
/// The `retarget convert` command line a batch worker runs for one clip, and the ConvertRequest
/// that command line makes (whose options hash the batch compares with a finished clip's
/// meta.json to decide whether it is up to date).

#include <optional>
#include <string>
#include <vector>

#include "retarget/batch/batch_clip.hpp"
#include "retarget/jobs/convert_job.hpp"
#include "retarget/reference/reference_io.hpp"

namespace rt {

/// The convert flags `retarget batch` forwards to every worker; a manifest's per-clip overrides
/// (ClipOverrides) replace the matching ones. Defaults are those of `retarget convert`.
struct ConvertSettings {
  std::vector<ReferenceFormat> formats{ReferenceFormat::Csv};  ///< --format
  std::string npz_layout;                    ///< --npz-layout (FILE absolute; "" = the robot's)
  double fps = 30.0;                         ///< [Hz] --fps
  double time_scale = 1.0;                   ///< --time-scale
  double max_joint_speed = 0;                ///< --max-joint-speed [rad/s] (0: none)
  std::string passes;                        ///< --passes ("" = default pipeline)
  std::vector<std::string> disabled_passes;  ///< --no-<pass>
  std::vector<std::string> enabled_passes;   ///< --<pass> (passes not in the default pipeline)
  std::optional<std::string> source_units;   ///< --source-units
  std::optional<double> source_fps;          ///< --source-fps [Hz]
  std::optional<std::string> up_axis;        ///< --up-axis
  std::string profile;                       ///< --skeleton-profile (absolute path; "" = none)
  bool keep_tpose = false;                   ///< --keep-tpose
  bool view = false;                         ///< --view (the viewer page; not part of the options hash)
  std::vector<std::string> package_paths;    ///< --package-path (absolute)
};

/// Arguments after the executable: `convert <input> --robot <robot> -o <stem>.csv --format ...`
/// plus every setting that differs from convert's default, and `--check --report <report_dir>`
/// when `report_dir` is not empty. `robot` should be an absolute robot.yaml path so that the
/// worker loads exactly the robot the batch hashed.
std::vector<std::string> convert_arguments(const BatchClip& clip, const ConvertSettings& settings,
                                           const std::string& robot, const std::string& output_stem,
                                           const std::string& report_dir);

/// The request `retarget convert` builds from convert_arguments(...) (same fields, same values).
ConvertRequest convert_request_for(const BatchClip& clip, const ConvertSettings& settings, const std::string& output_stem);

}  // namespace rt
