#pragma once
/// `retarget batch` as a library function (design.md §1): finds the clips, picks this shard's,
/// skips the up-to-date ones, runs `retarget convert` for the others in parallel worker processes
/// (separate processes: Ipopt and MUMPS are not thread-safe, and a crash in one clip must not take
/// down the batch), records each clip's outcome and returns the summary. Never prints: progress
/// goes through callbacks, and the caller writes the summary (write_summary) — run_batch writes
/// it too, into the output folder, before returning.
///
/// No two batches may write one clip of an output folder at a time, whatever their shard tags:
/// run_batch holds a lock on each of its clips in `<out>/.retarget-batch.lock` (fcntl byte locks,
/// released by the kernel when the process dies, so a `kill -9` never leaves them stale). Shards of
/// one `--shard I/N` split hold disjoint clips and run side by side; a plain batch and a
/// `--shard 1/1` one into the same folder do not.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "retarget/batch/batch_clip.hpp"
#include "retarget/batch/batch_progress.hpp"
#include "retarget/batch/batch_summary.hpp"
#include "retarget/batch/clip_discovery.hpp"
#include "retarget/batch/convert_command.hpp"
#include "retarget/batch/shard.hpp"

namespace rt {

/// Default per-worker address-space limit: generous for the largest clips (a 60 s clip peaks near
/// 150 MB resident) but finite, so a runaway allocation fails instead of swapping. Address space
/// is larger than resident memory (shared libraries, thread stacks), hence the margin.
/// AddressSanitizer builds reserve terabytes of address space, so there the default is no limit.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr std::uint64_t kDefaultWorkerMemoryLimitBytes = 0;
#else
inline constexpr std::uint64_t kDefaultWorkerMemoryLimitBytes = std::uint64_t{4} << 30;
#endif

struct BatchOptions {
  std::string input;                   ///< folder or manifest (.yaml/.yml/.csv)
  std::string robot = "humanoid25";    ///< name, folder or robot.yaml (as for convert)
  std::string output_dir;              ///< required
  int jobs = 0;                        ///< parallel workers; 0 = available_cpus()
  bool check = false;                  ///< run the dynamics check after each conversion
  ConvertSettings convert;             ///< convert flags for every clip
  std::optional<ShardSpec> shard;      ///< process only this shard
  bool force = false;                  ///< redo up-to-date clips
  bool fail_fast = false;              ///< stop at the first failed clip (running ones are cancelled)
  bool allow_outside = false;          ///< accept manifest paths outside the input root
  double timeout_s = 3600;             ///< [s] per-clip wall-clock limit; 0 = none
  std::uint64_t memory_limit_bytes = kDefaultWorkerMemoryLimitBytes;  ///< per worker; 0 = none
  /// The program run as `<worker_executable> convert ...`: the retarget binary (the CLI passes
  /// /proc/self/exe). Tests substitute a fake worker.
  std::string worker_executable;
  double stop_grace_s = 3.0;           ///< [s] after SIGTERM before SIGKILL when stopping workers
  double poll_s = 0.02;                ///< [s] worker polling period
};

/// What a batch would do, before it runs.
struct PlannedClip {
  BatchClip clip;
  bool up_to_date = false;
  std::string reason;  ///< why it is (not) up to date
};

struct BatchPlan {
  std::string robot_name, robot_config;
  std::vector<PlannedClip> clips;  ///< this shard's clips, largest input first (the run order)
  int total_clips = 0;             ///< before sharding
};

struct BatchCallbacks {
  /// After every state change and about once a second.
  std::function<void(const BatchProgress&)> on_progress;
  /// When a clip finishes (skipped ones included), with the progress after it.
  std::function<void(const ClipResult&, const BatchProgress&)> on_clip;
  /// Polled while running: a non-empty return (e.g. "SIGINT") stops the batch — no new workers,
  /// running ones get SIGTERM, then SIGKILL after stop_grace_s — and is recorded as `stopped`.
  std::function<std::string()> stop_requested;
};

/// Discovers, shards and checks the clips (loads the robot once, so a bad robot fails here with
/// InputError). Writes nothing.
BatchPlan plan_batch(const BatchOptions& options);

/// Runs the batch and writes summary files into the output folder (names per summary_file_names,
/// tagged with the shard). InputError for a bad input, robot or output folder, or a locked
/// output folder; clip failures are recorded, never thrown. The process must not otherwise reap
/// its children (no SIGCHLD SIG_IGN).
BatchSummary run_batch(const BatchOptions& options, const BatchCallbacks& callbacks = {});

/// One line with the convert flags every worker gets (for the summary and --dry-run).
std::string describe_convert_settings(const ConvertSettings& settings, bool check);

}  // namespace rt
