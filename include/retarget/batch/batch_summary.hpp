#pragma once
/// The record of a batch (design.md §5 "an HTML index for batches"): one ClipResult per clip,
/// written as summary.json (machines), summary.csv (spreadsheets) and index.html (people), and
/// merged across shards by `retarget merge-summaries`.
///
/// summary.json, format "retarget-batch-summary", format_version 1 (readers reject other formats
/// and newer versions; keys may be added within a version):
///
///   {
///     "format": "retarget-batch-summary", "format_version": 1, "tool_version": "0.1.0",
///     "robot": "g1", "robot_config": "/abs/robots/g1/robot.yaml",
///     "input": "/abs/mocap",                  // folder or manifest
///     "shard": "2/3",                         // null when not sharded (and in a merged summary)
///     "merged_from": ["out/summary-shard-1-of-3.json", ...],  // only in a merged summary
///     "check": true, "convert_options": "--format csv --fps 30",
///     "jobs": 8, "started_utc": "2024-05-01T12:00:00Z", "wall_s": 512.3,
///     "stopped": null,                        // or why the batch stopped early ("SIGINT", "--fail-fast")
///     "exit_status": 1,                       // batch_exit_status() of this summary
///     "counts": {"total": 40, "ok": 35, "check-failed": 2, "bad-input": 1, ...},  // every status
///     "clips": [                              // sorted by name
///       {"name": "walks/walk01", "input": "/abs/mocap/walks/walk01.bvh", "input_bytes": 716137,
///        "status": "ok",                      // see ClipStatus
///        "error": null,                       // one line for failures
///        "exit_code": 0, "signal": null,      // of the worker (null when none ran)
///        "time_s": 3.2, "peak_rss_mb": 121.5, // worker wall time and peak memory (0 when skipped)
///        "frames": 249, "fps": 30, "duration_s": 8.27, "source_frames": 994,
///        "landmark_error_median_m": 0.031, "landmark_error_p95_m": 0.058,
///        "foot_skating_p95_m": 0.004, "penetration_max_m": 0.001,
///        "check": "passed",                   // "passed", "failed" or "not-run"
///        "violations": 2, "main_violation": "cop-near-edge at 1.20 s: ...",
///        "files": {"data": ["walks/walk01.csv"], "meta": "walks/walk01.meta.json",
///                  "log": "walks/walk01.log", "report": "walks/walk01.report/report.json",
///                  "report_text": "...", "plots": ["walks/walk01.report/com_cop_y.svg", ...]}}
///     ]
///   }
///
/// Metrics a clip does not have (failed clips) are null. File paths are relative to the
/// summary's folder (merge-summaries rewrites them for its output folder).
///
/// summary.csv: a header row, then one row per clip: name, status, frames, fps, duration_s,
/// time_s, peak_rss_mb, landmark_error_median_m, landmark_error_p95_m, foot_skating_p95_m,
/// penetration_max_m, check, violations, main_violation, error, input, data, log, report
/// (RFC 4180 quoting; empty cells for missing values).
///
/// Exit status of a batch (batch_exit_status), in precedence order:
///   2  some clip had bad input or failed otherwise (crashed, timeout, out-of-memory, error,
///      cancelled)
///   1  otherwise, some clip failed its dynamics check (also when skipped: the stored report of
///      an up-to-date clip still counts)
///   0  every clip succeeded (ok, or skipped as up to date)

#include <cstdint>
#include <string>
#include <vector>

#include "retarget/core/version.hpp"

namespace rt {

enum class ClipStatus {
  Ok,           ///< converted (and, with --check, the check passed)
  CheckFailed,  ///< converted, but the dynamics check failed (outputs and report written)
  BadInput,     ///< the clip (or a setting for it) is malformed: convert exited with status 2
  Crashed,      ///< the worker died from a signal
  Timeout,      ///< the worker ran past the per-clip timeout and was killed
  OutOfMemory,  ///< the worker ran out of memory (its address-space limit)
  Error,        ///< any other failure (internal error, unexpected exit status, missing outputs)
  Skipped,      ///< up to date from an earlier run (not redone; --force redoes it)
  Cancelled,    ///< not finished because the batch stopped (signal or --fail-fast)
};

/// "ok", "check-failed", "bad-input", "crashed", "timeout", "out-of-memory", "error", "skipped",
/// "cancelled".
const char* clip_status_name(ClipStatus status);
/// Inverse of clip_status_name; InputError at `where` for unknown names.
ClipStatus parse_clip_status(const std::string& name, const std::string& where);
/// All statuses in declaration order.
const std::vector<ClipStatus>& all_clip_statuses();

enum class CheckOutcome { NotRun, Passed, Failed };
/// "not-run", "passed", "failed".
const char* check_outcome_name(CheckOutcome outcome);

/// Files of one clip, relative to the summary's folder ("" / empty when absent).
struct ClipFiles {
  std::vector<std::string> data;  ///< .csv / .npz
  std::string meta, log, report, report_text;
  std::vector<std::string> plots;  ///< SVG plots of the check
  std::string view;                ///< the motion viewer page (batch --view)
};

struct ClipResult {
  std::string name;             ///< output name (unique in a batch)
  std::string input;            ///< absolute input path
  std::uint64_t input_bytes = 0;
  ClipStatus status = ClipStatus::Error;
  std::string error;            ///< one line; empty unless the clip failed or was cancelled
  int exit_code = -1;           ///< worker exit code; -1 when none (skipped, signal, not started)
  int signal = 0;               ///< signal that ended the worker; 0 when none
  double time_s = 0;            ///< [s] worker wall time; 0 when skipped
  double peak_rss_mb = 0;       ///< [MiB] worker peak resident memory; 0 when skipped

  // From the clip's meta.json (ok, check-failed, skipped); NaN / -1 when unknown.
  int frames = -1;              ///< output frames
  double fps = 0;               ///< [Hz] output rate
  double duration_s = -1;
  int source_frames = -1;
  double landmark_error_median_m = -1, landmark_error_p95_m = -1;  ///< -1 when unknown
  double foot_skating_p95_m = -1, penetration_max_m = -1;         ///< -1 when unknown

  // From the clip's report.json (with --check).
  CheckOutcome check = CheckOutcome::NotRun;
  int violations = -1;          ///< -1 when unknown
  std::string main_violation;   ///< first failing violation, else the first one; "" when none

  ClipFiles files;

  /// The clip counts as a failed check (status check-failed, or skipped with a failed report).
  bool check_failed() const;
  /// The clip counts as a failure of exit status 2 (see the file comment).
  bool hard_failure() const;
};

struct BatchSummary {
  std::string tool_version = kVersion;
  std::string robot;                      ///< robot name
  std::string robot_config;               ///< robot.yaml path
  std::string input;                      ///< batch input (folder or manifest)
  std::string shard;                      ///< "I/N"; "" when not sharded
  std::vector<std::string> merged_from;   ///< summaries merged into this one
  bool check = false;                     ///< --check
  std::string convert_options;            ///< the convert flags every worker got (one line)
  int jobs = 0;
  std::string started_utc;                ///< ISO 8601, e.g. "2024-05-01T12:00:00Z"
  double wall_s = 0;                      ///< [s]
  std::string stopped;                    ///< why the batch stopped early; "" when it finished
  std::vector<ClipResult> clips;          ///< sorted by name (sort_clips)

  void sort_clips();
  /// Clips with `status`.
  int count(ClipStatus status) const;
};

/// 0, 1 or 2 by the precedence in the file comment.
int batch_exit_status(const BatchSummary& summary);

std::string summary_json(const BatchSummary& summary);
std::string summary_csv(const BatchSummary& summary);
/// index.html: counts, then a table of every clip with links to its files, report and plots.
/// Self-contained (inline CSS), every text HTML-escaped, links percent-encoded.
std::string summary_html(const BatchSummary& summary);

/// File names of a summary: "summary.json", "summary.csv", "index.html", or with a tag
/// ("shard-2-of-3"): "summary-shard-2-of-3.json", ..., "index-shard-2-of-3.html".
struct SummaryFileNames {
  std::string json, csv, html;
};
SummaryFileNames summary_file_names(const std::string& tag);

/// Writes the three files into `folder` (created when missing), each atomically. Returns their
/// paths (json, csv, html). InputError when the folder cannot be written.
std::vector<std::string> write_summary(const std::string& folder, const BatchSummary& summary,
                                       const std::string& tag = "");

/// Parses summary.json text (`file` names it in errors): InputError "file:line:col" for malformed
/// JSON and "file [clips[3].status]" for a missing key or a bad value.
BatchSummary parse_summary(const std::string& text, const std::string& file);
BatchSummary read_summary(const std::string& path);

/// Merges shard summaries into one for `out_folder`: the clips of all of them, file links
/// rewritten relative to `out_folder`, counts and exit status recomputed, jobs summed, wall time
/// the longest, start time the earliest, `stopped` kept when any shard stopped early. The input is
/// the shards' common input ("" when they differ: machines may mount the data elsewhere).
/// InputError when a summary cannot be read, when they name different robots, check settings or
/// convert options, when two list the same clip name, or when they are shards "I/N" of one split
/// and a shard is missing.
BatchSummary merge_summaries(const std::vector<std::string>& summary_paths, const std::string& out_folder);

}  // namespace rt
