#pragma once
/// A batch worker: one child process (fork + exec) with its own process group, its stdout and
/// stderr captured in a log file, an address-space limit and a wall-clock timeout. Used by the
/// batch runner for every clip and by tests that run the `retarget` tool.
///
/// The child: gets its own process group (so a timeout kills everything it started, and a
/// terminal's Ctrl-C reaches only the batch, which then stops its workers); dies with its parent
/// (PR_SET_PDEATHSIG, so a `kill -9` of the batch leaves no orphan writing outputs); starts with
/// an empty signal mask and default signal handlers; reads /dev/null; and runs with
/// RLIMIT_AS = memory_limit_bytes when that is not 0. The limit makes a runaway allocation fail
/// (std::bad_alloc) instead of pushing the machine into swap.

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace rt {

struct WorkerLaunch {
  std::vector<std::string> argv;         ///< argv[0] is the executable path (no PATH search)
  std::vector<std::string> extra_env;    ///< "NAME=value" added to (or replacing in) the environment
  std::string log_path;                  ///< stdout + stderr go here (truncated); "" = /dev/null
  std::string working_dir;               ///< "" = the parent's
  double timeout_s = 0;                  ///< [s] wall-clock limit; 0 = none
  std::uint64_t memory_limit_bytes = 0;  ///< RLIMIT_AS of the child; 0 = none
};

/// How a worker ended.
struct WorkerExit {
  bool exited = false;      ///< it called exit(); exit_code is valid
  int exit_code = -1;
  int signal = 0;           ///< the signal that ended it (0 when it exited)
  bool timed_out = false;   ///< killed by us for exceeding timeout_s
  bool cancelled = false;   ///< killed by us through terminate()
  double wall_s = 0;        ///< [s] from start to reaping
  double max_rss_mb = 0;    ///< [MiB] peak resident set size (getrusage ru_maxrss)
};

/// A running worker. Not copyable; the destructor kills and reaps a worker still running.
class WorkerProcess {
 public:
  /// Starts the process. InputError when the log file cannot be created; an executable that
  /// cannot be run shows up as exit code 127 with the reason in the log.
  explicit WorkerProcess(const WorkerLaunch& launch);
  ~WorkerProcess();
  WorkerProcess(const WorkerProcess&) = delete;
  WorkerProcess& operator=(const WorkerProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running() const { return running_; }

  /// Non-blocking: reaps the process when it has ended and kills its group when it is past its
  /// timeout. Returns true once it has ended (then exit() is valid).
  bool poll();
  /// Sends `sig` to the worker's process group (SIGTERM for a clean stop, SIGKILL to force).
  /// Marks the exit as cancelled. No effect once it has been reaped.
  void terminate(int sig);
  /// Blocks until the process ends, polling every `poll_s`; still enforces the timeout.
  const WorkerExit& wait(double poll_s = 0.01);
  const WorkerExit& exit() const { return exit_; }
  /// [s] since the start.
  double elapsed_s() const;

 private:
  void reap(int status, long max_rss_kb);

  pid_t pid_ = -1;
  bool running_ = false;
  double timeout_s_ = 0;
  std::chrono::steady_clock::time_point start_;
  WorkerExit exit_;
};

/// Runs a process to completion (WorkerProcess + wait).
WorkerExit run_worker(const WorkerLaunch& launch);

/// "SIGSEGV (Segmentation fault)".
std::string signal_description(int sig);

/// Number of CPUs this process may run on (sched_getaffinity: honours cgroups/Slurm cpusets), >= 1.
int available_cpus();

}  // namespace rt
