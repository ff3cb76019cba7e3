#include "cli/print_check.hpp"

#include <iostream>

#include "cli/exit_codes.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/report/check_report.hpp"

namespace rt::cli {

int report_check(const RobotModel& model, const ValidateResult& r, const DynamicsCheckOptions& options,
                 const std::string& reference_path, const std::string& report_dir, bool json) {
  const ReportInfo info = make_report_info(model.name(), reference_path, options);
  if (json)
    std::cout << check_report_json(r.check, info) << "\n";
  else
    std::cout << format_check_summary(r.check, info);
  if (!report_dir.empty()) {
    const auto files = write_check_report(report_dir, r.check, info);
    if (!json) std::cout << "  report      " << join(files, ", ") << "\n";
  }
  for (const Diagnostic& d : r.diagnostics.items()) std::cerr << d.to_string() << "\n";
  return r.check.passed ? kExitOk : kExitCheckFailed;
}

}  // namespace rt::cli
