#pragma once
/// A clip's files in the output folder, whether they are a finished, up-to-date result (resume),
/// and what they say (the summary's per-clip metrics).
///
/// For output name `walks/walk01` in folder `out`:
///   out/walks/walk01.csv, .npz     the reference (per --format)
///   out/walks/walk01.meta.json     written last by convert: its presence marks complete data files
///   out/walks/walk01.log           the worker's stdout + stderr
///   out/walks/walk01.report/       report.json, report.txt and SVG plots (with --check)
///   out/walks/walk01.html          the motion viewer page (with --view; linked whenever present)
///   out/walks/walk01.complete      the completion marker, written by the batch last of all
///
/// Up to date (the clip is skipped unless --force) when all of these hold:
///   - meta.json exists, parses, and is newer than the input file;
///   - its recorded source.sha256, robot_config.sha256, urdf_sha256 and options_sha256 equal the
///     current ones (input content, robot.yaml, URDF, convert_options_sha256 of the request);
///   - every data file of the requested formats exists and is listed in the meta's `files`;
///   - with --check: report.json exists, parses, and is not older than meta.json;
///   - the completion marker exists and every file it lists (data, meta, log and, with --check,
///     each file of the report folder) still has the size it recorded, and meta.json the same
///     SHA-256. The batch writes the marker only after the worker exited and its outputs were
///     read back complete, and removes it before a worker is started on the clip, so a worker
///     killed at any moment (or a full disk) leaves a clip that the next run redoes.
/// A data file without a meta (a crash between the two writes) or a stale temporary
/// (`*.tmp.<pid>.<n>` of write_file_atomic) is therefore never taken for a finished output;
/// remove_stale_temporaries() deletes such temporaries before a clip is redone.

#include <string>
#include <vector>

#include "retarget/batch/batch_summary.hpp"
#include "retarget/reference/reference_io.hpp"

namespace rt {

struct ClipOutputPaths {
  std::string stem;        ///< out/walks/walk01
  std::vector<std::string> data;  ///< stem + .csv / .npz, per format
  std::string meta;        ///< stem + .meta.json
  std::string log;         ///< stem + .log
  std::string report_dir;  ///< stem + .report
  std::string report;      ///< report_dir + /report.json
  std::string complete;    ///< stem + .complete (the completion marker)
  std::string view;        ///< stem + .html (the motion viewer page, with --view)
};

ClipOutputPaths clip_output_paths(const std::string& out_folder, const std::string& output_name,
                                  const std::vector<ReferenceFormat>& formats);

/// Hashes a finished clip's meta.json must record for it to be up to date.
struct ExpectedHashes {
  std::string source_sha256;        ///< of the input file; "" when it cannot be read (never up to date)
  std::string robot_config_sha256;
  std::string urdf_sha256;
  std::string options_sha256;       ///< convert_options_sha256 of the clip's request
};

struct UpToDate {
  bool up_to_date = false;
  std::string reason;  ///< why not (for --dry-run): "no meta.json", "options changed", ...
};

/// The resume rule above. Never throws for unreadable or malformed outputs (they are just not up
/// to date).
UpToDate check_up_to_date(const std::string& input, const ClipOutputPaths& paths, const ExpectedHashes& expected,
                          bool check);

/// Writes the completion marker (format `retarget-clip-complete`: every output file of the clip
/// with its size, meta.json with its SHA-256) atomically. Call it after the outputs were read back
/// complete. InputError when the marker cannot be written.
void write_completion_marker(const ClipOutputPaths& paths, bool check);

/// Removes the completion marker (before a worker is started on the clip); absent is fine.
void remove_completion_marker(const ClipOutputPaths& paths);

/// Deletes `<file>.tmp.*` temporaries left by an interrupted atomic write of any of the clip's
/// files (data, meta, report folder). Returns how many were removed.
int remove_stale_temporaries(const ClipOutputPaths& paths);

/// Fills the metrics and file links of `result` from the clip's meta.json and (when `check`) its
/// report.json; file links are made relative to `out_folder`. Returns "" on success, else what
/// was missing or malformed (one line) — the caller decides whether that is a failure.
std::string read_clip_outputs(ClipResult& result, const ClipOutputPaths& paths, const std::string& out_folder,
                              bool check);

}  // namespace rt
