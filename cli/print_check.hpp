#pragma once
/// Output of a dynamics check for `validate` and `convert --check`: the text summary (or the JSON
/// report) on stdout, the report folder when asked, and the exit status.

#include <string>

#include "retarget/jobs/validate_job.hpp"

namespace rt::cli {

/// Prints (and writes, when `report_dir` is not empty) the check result run with `options`; returns
/// kExitOk when the check passed, kExitCheckFailed otherwise.
int report_check(const RobotModel& model, const ValidateResult& result, const DynamicsCheckOptions& options,
                 const std::string& reference_path, const std::string& report_dir, bool json);

}  // namespace rt::cli
