#pragma once
/// The report of a dynamics check (design.md §3.5, §5 "Report"): `report.json` for machines,
/// `report.txt` for people (the same text `retarget validate` prints) and SVG plots
/// (check_plots.hpp), written into one folder.
///
/// report.json, format "retarget-check-report", format_version 1 (a reader must reject other
/// formats and newer major versions; keys may be added within a version):
///
///   {
///     "format": "retarget-check-report", "format_version": 1,
///     "tool_version": "0.1.0",
///     "robot": "humanoid25",
///     "reference": "out/walk.csv",                       // as the user gave it
///     "options": {"dynamic_mapping": true, "trunk_mapping": true, "summary": "control 2 ms, ..."},
///     "passed": false,                                   // no violation with fails_check
///     "fell": true,
///     "fall_time_s": 1.234,                              // null when it did not fall
///     "clip_duration_s": 5.0, "simulated_s": 1.234,      // clip time simulated (settling excluded)
///     "wall_s": 0.21, "real_time_factor": 8.3,           // simulated s (settling included) per wall s
///     "metrics": {
///       "joint_rms_error_rad": 0.012, "com_rms_error_m": 0.004, "com_max_error_m": 0.011,
///       "cop_rms_error_m": 0.006, "saturated_control_cycles": 3, "trunk_mapping_updates": 2,
///       "replans": 1, "violations": 2, "failing_violations": 1
///     },
///     "violations": [                                    // sorted by start time
///       {"kind": "cop-near-edge", "start_s": 0.8, "end_s": 0.95, "magnitude": -0.004, "unit": "m",
///        "detail": "COP 0.004 m inside the support polygon's edge", "fails_check": false},
///       {"kind": "fall", "start_s": 1.234, "end_s": 1.234, "magnitude": 1, "unit": "",
///        "detail": "link 'r_hand' touched the floor", "fails_check": true}
///     ],
///     "replans": [                                       // online dynamic-mapping activations (kind: ReplanEvent::kind)
///       {"t_s": 0.5, "kind": 1, "n": 37, "predicted_cop_w": [0.01, -0.02], "ref_cop_w": [0.01, 0.05],
///        "after_cop_w": [0.01, 0.049], "max_shift_m": 0.031}
///     ],
///     "balance_plan": {                                  // walking controller only (DynamicsCheckResult::walking)
///       "max_com_shift_m": 0.05, ..., "max_dcm_error_m": 0.03,
///       "lead_in_s": 0.3, "lead_in_foot": "left",        // standing lead-in; foot null when none
///       "lead_in_root_drop_m": 0.0,                      // root lowered so the foot reached the floor
///       "lead_in_skipped": null                          // why a clip starting on one foot got none
///     },
///     "trace": {                                         // recorded time series, column-wise
///       "source_samples": 500, "stride": 1, "samples": 500,
///       "t_s": [...],                                    // clip time [s]
///       "com_w": [[x, y, z], ...],                       // actual COM [m]
///       "com_ref_w": [[x, y], ...],                      // reference COM after re-planning [m]
///       "com_ref_original_w": [[x, y], ...],             // reference COM before re-planning [m]
///       "cop_w": [[x, y], ...],                          // measured COP [m]; null when nothing touches
///       "cop_desired_w": [[x, y], ...],                  // balance controller output [m]
///       "support_min_w": [[x, y], ...], "support_max_w": [[x, y], ...],  // support bounding box; null when none
///       "contact_ref": [[1, 1], ...], "contact_actual": [[1, 0], ...],   // left, right: 1 in contact
///       "foot_force_n": [[l, r], ...],                   // normal force per foot [N]
///       "tracking_error_rad": [[legs, torso, arms, all], ...]  // RMS joint error per group [rad]
///     }
///   }
///
/// Numbers: lengths, angles and times are rounded to 1e-6, forces to 1e-3 N, so files stay
/// compact and the text is the same for the same result. A NaN is written as null.
/// Trace downsampling: a trace longer than kMaxReportTraceSamples keeps every `stride`-th sample,
/// stride = ceil(source_samples / kMaxReportTraceSamples), plus always the last sample (so the
/// trace still ends where the run ended). At the default 10 ms record period that keeps every
/// sample of clips up to 40 s; the file stays below about 1 MB at any length. Violations and
/// re-plans are never downsampled, and the plots use the full trace.

#include <string>
#include <vector>

#include "retarget/core/version.hpp"
#include "retarget/sim/dynamics_check.hpp"
#include "retarget/sim/violations.hpp"

namespace rt {

inline constexpr const char* kCheckReportFormat = "retarget-check-report";
inline constexpr int kCheckReportFormatVersion = 1;
/// Trace samples kept in report.json before downsampling (see above).
inline constexpr int kMaxReportTraceSamples = 4000;

/// What the report needs that the result does not carry.
struct ReportInfo {
  std::string robot;               ///< robot name
  std::string reference_path;      ///< the checked reference, as given by the user
  bool dynamic_mapping = true;     ///< DynamicsCheckOptions::dynamic_mapping of the run
  bool trunk_mapping = true;       ///< DynamicsCheckOptions::trunk_mapping of the run
  std::string options_summary;     ///< other settings worth recording, one line (may be empty)
  std::string tool_version = kVersion;
};

/// ReportInfo for a run with `options`: the mapping switches and a one-line summary of the
/// controller and threshold settings.
ReportInfo make_report_info(const std::string& robot, const std::string& reference_path,
                            const DynamicsCheckOptions& options);

/// Human-readable summary: verdict, tracking metrics, violations grouped by kind and the first
/// ones listed (failing ones first). Ends with a newline. Used for stdout and report.txt.
std::string format_check_summary(const DynamicsCheckResult& result, const ReportInfo& info);

/// report.json text (see above).
std::string check_report_json(const DynamicsCheckResult& result, const ReportInfo& info);

/// Writes report.json, report.txt, com_cop_y.svg, com_cop_x.svg, contacts.svg and tracking.svg
/// into `folder` (created when missing), each atomically. Returns the paths written, in that
/// order. InputError when the folder cannot be created or written.
std::vector<std::string> write_check_report(const std::string& folder, const DynamicsCheckResult& result,
                                            const ReportInfo& info);

/// The main fields of a report.json, read back (tests, batch summaries).
struct CheckReportSummary {
  int format_version = 0;
  std::string tool_version, robot, reference_path;
  bool dynamic_mapping = true, trunk_mapping = true;
  bool passed = false;
  bool fell = false;
  double fall_time_s = -1;  ///< -1 when it did not fall
  double clip_duration_s = 0, simulated_s = 0, wall_s = 0, real_time_factor = 0;
  double joint_rms_error_rad = 0;
  double com_rms_error_m = 0, com_max_error_m = 0;
  double cop_rms_error_m = 0;
  int saturated_control_cycles = 0;
  int trunk_mapping_updates = 0;
  int num_replans = 0;
  int trace_samples = 0;
  std::vector<Violation> violations;
};

/// Parses report.json text; `file` names it in errors. InputError with `file:line:col` for
/// malformed JSON and `file [key.path]` for a missing key or a value of the wrong type or range.
CheckReportSummary parse_check_report(const std::string& text, const std::string& file);
/// Reads and parses a report.json.
CheckReportSummary read_check_report(const std::string& path);

}  // namespace rt
