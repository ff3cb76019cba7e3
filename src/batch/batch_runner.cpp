#include "retarget/batch/batch_runner.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include "retarget/batch/clip_outputs.hpp"
#include "retarget/batch/worker_process.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/sha256.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/robot_config.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::size_t kLogTailBytes = 64 * 1024;
constexpr std::size_t kMaxErrorChars = 600;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string absolute_path(const std::string& p) {
  std::error_code ec;
  const fs::path a = fs::absolute(p, ec);
  return (ec ? fs::path(p) : a).lexically_normal().string();
}

// The last part of a worker's log.
std::string log_tail(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff from = std::max<std::streamoff>(0, size - static_cast<std::streamoff>(kLogTailBytes));
  in.seekg(from);
  std::string text(static_cast<std::size_t>(size - from), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  return text;
}

// The error a worker reported: its last "error: ..." / "internal error: ..." line (the CLI's
// format), else its last non-empty line.
std::string worker_error(const std::string& tail) {
  std::string last_error, last_line;
  for (const std::string& raw : split(tail, "\n")) {
    const std::string line(trim(raw));
    if (line.empty()) continue;
    last_line = line;
    if (starts_with(line, "error: ")) last_error = line.substr(7);
    else if (starts_with(line, "internal error: ")) last_error = line;
  }
  std::string e = last_error.empty() ? last_line : last_error;
  if (e.size() > kMaxErrorChars) e = e.substr(0, kMaxErrorChars) + "...";
  return e;
}

bool mentions_out_of_memory(const std::string& tail) {
  const std::string t = to_lower(tail);
  return t.find("bad_alloc") != std::string::npos || t.find("cannot allocate memory") != std::string::npos ||
         t.find("out of memory") != std::string::npos || t.find("out-of-memory") != std::string::npos;
}

// Environment for workers: one thread for BLAS/OpenMP inside each (the batch parallelises by
// processes), unless the user set these.
std::vector<std::string> worker_environment() {
  std::vector<std::string> env;
  for (const char* name : {"OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"})
    if (!std::getenv(name)) env.push_back(std::string(name) + "=1");
  return env;
}

// One lock file per output folder, whatever the shard tag: each batch holds a write lock
// (fcntl, 1 byte at an offset hashed from the clip's output name) on every clip it plans, for its
// lifetime. Shards of one split own disjoint clips and run side by side; a plain batch and a
// `--shard 1/1` one, or shards of different splits, share clips and the second one is refused
// before it touches a file. fcntl locks also work over NFS (lockd), unlike flock on some systems.
class ClipLocks {
 public:
  ClipLocks(const std::string& path, const std::vector<PlannedClip>& clips) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw InputError(path, std::string("cannot create the batch lock file: ") + std::strerror(errno));
    for (const PlannedClip& c : clips) {
      struct flock l {};
      l.l_type = F_WRLCK;
      l.l_whence = SEEK_SET;
      l.l_start = static_cast<off_t>(name_hash(c.clip.output_name) >> 2);  // < 2^62: a valid offset
      l.l_len = 1;
      if (::fcntl(fd_, F_SETLK, &l) != 0) {
        const int err = errno;
        ::close(fd_);
        if (err != EACCES && err != EAGAIN)
          throw InputError(path, std::string("cannot lock the output folder: ") + std::strerror(err));
        throw InputError(path, "another retarget batch is writing clip '" + c.clip.output_name +
                                   "' into this output folder (lock held); wait for it or use another -o");
      }
    }
  }
  ~ClipLocks() {
    if (fd_ >= 0) ::close(fd_);  // releases the locks
  }
  ClipLocks(const ClipLocks&) = delete;
  ClipLocks& operator=(const ClipLocks&) = delete;

 private:
  static std::uint64_t name_hash(const std::string& s) {  // FNV-1a
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
  }
  int fd_ = -1;
};

fs::path resolved_path(const fs::path& p) {
  std::error_code ec;
  const fs::path r = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : r;
}

bool path_within(const fs::path& root, const fs::path& p) {
  const fs::path rel = p.lexically_relative(root);
  return !rel.empty() && rel.begin()->string() != ".." && !rel.is_absolute();
}

// Paths are checked again right before a worker starts, not only at planning: a symlink that
// dangled then (or was changed since) must not lead the worker outside the input root, and an
// output name must not lead through a symlink inside -o to a folder outside it. Throws InputError.
void check_paths_at_launch(const BatchClip& clip, const ClipOutputPaths& paths, const std::string& output_dir) {
  if (!clip.input_root.empty() && !path_within(fs::path(clip.input_root), resolved_path(clip.input)))
    throw InputError(clip.input, "now resolves outside the input root " + clip.input_root +
                                     " (a symlink changed since planning; pass --allow-outside to accept it)");
  const fs::path out = resolved_path(fs::absolute(output_dir));
  if (!path_within(out, resolved_path(fs::absolute(paths.stem))))
    throw InputError(paths.stem, "the output path leads outside the output folder " + out.string() + " (through a symlink)");
}

struct Running {
  std::size_t index = 0;  // into the plan
  ClipOutputPaths paths;
  std::unique_ptr<WorkerProcess> process;
};

ClipResult base_result(const BatchClip& clip) {
  ClipResult r;
  r.name = clip.output_name;
  r.input = clip.input;
  r.input_bytes = clip.input_bytes;
  return r;
}

// A finished worker -> the clip's result (status, error, metrics from its outputs).
ClipResult finished_result(const BatchClip& clip, const WorkerExit& x, const ClipOutputPaths& paths,
                           const BatchOptions& o, const std::string& stop_reason) {
  ClipResult r = base_result(clip);
  r.time_s = x.wall_s;
  r.peak_rss_mb = x.max_rss_mb;
  r.exit_code = x.exited ? x.exit_code : -1;
  r.signal = x.signal;
  const std::string tail = log_tail(paths.log);
  const bool produced = x.exited && (x.exit_code == 0 || (o.check && x.exit_code == 1));
  if (x.timed_out) {
    r.status = ClipStatus::Timeout;
    r.error = format("exceeded the per-clip timeout of %g s; the worker's process group was killed", o.timeout_s);
  } else if (x.cancelled && !produced) {
    r.status = ClipStatus::Cancelled;
    r.error = "stopped: " + (stop_reason.empty() ? std::string("batch stopped") : stop_reason);
  } else if (!x.exited && x.signal == 0) {
    r.status = ClipStatus::Error;
    r.error = "the worker's exit status was lost (was SIGCHLD ignored?)";
  } else if (!x.exited) {
    const bool oom = mentions_out_of_memory(tail);
    r.status = oom ? ClipStatus::OutOfMemory : ClipStatus::Crashed;
    r.error = (oom ? "ran out of memory and died from " : "crashed: ") + signal_description(x.signal);
    const std::string last = worker_error(tail);
    if (!last.empty()) r.error += " (log: " + last + ")";
  } else if (produced) {
    const std::string problem = read_clip_outputs(r, paths, o.output_dir, o.check);
    if (!problem.empty()) {
      r.status = ClipStatus::Error;
      r.error = format("the worker exited with status %d but ", x.exit_code) + problem;
    } else if (x.exit_code == 1 || r.check == CheckOutcome::Failed) {
      r.status = ClipStatus::CheckFailed;
      r.error = "";
    } else {
      r.status = ClipStatus::Ok;
    }
    return r;
  } else if (x.exit_code == 2) {
    r.status = ClipStatus::BadInput;
    r.error = worker_error(tail);
  } else if (mentions_out_of_memory(tail)) {
    r.status = ClipStatus::OutOfMemory;
    r.error = o.memory_limit_bytes > 0
                  ? format("ran out of memory (worker limit %.0f MiB, --memory-limit)", static_cast<double>(o.memory_limit_bytes) / (1 << 20))
                  : std::string("ran out of memory");
    const std::string last = worker_error(tail);
    if (!last.empty()) r.error += ": " + last;
  } else {
    r.status = ClipStatus::Error;
    const std::string last = worker_error(tail);
    r.error = format("the worker exited with status %d", x.exit_code) + (last.empty() ? std::string() : ": " + last);
  }
  // Link the log only: outputs of an earlier run may still be there, but they are not this run's.
  ClipResult files;
  read_clip_outputs(files, paths, o.output_dir, false);
  r.files.log = files.files.log;
  return r;
}

std::string robot_argument(const BatchPlan& plan) { return absolute_path(plan.robot_config); }

}  // namespace

std::string describe_convert_settings(const ConvertSettings& settings, bool check) {
  ConvertSettings s = settings;
  s.package_paths.clear();  // where the URDF is found, not what is computed (its hash is checked)
  const std::vector<std::string> a = convert_arguments(BatchClip{}, s, "", "", "");
  std::vector<std::string> flags(a.begin() + 6, a.end());  // after: convert <clip> --robot <r> -o <out>
  if (check) flags.push_back("--check");
  for (std::string& f : flags)
    if (f.find_first_of(" \t'\"") != std::string::npos || f.empty()) f = "'" + f + "'";
  return join(flags, " ");
}

BatchPlan plan_batch(const BatchOptions& o) {
  if (o.output_dir.empty()) throw InputError("-o", "an output folder is required (retarget batch INPUT -o OUTDIR)");
  if (o.convert.formats.empty()) throw InputError("--format", "no output format");
  BatchPlan plan;
  std::vector<BatchClip> clips = discover_clips(o.input, {o.allow_outside});
  plan.total_clips = static_cast<int>(clips.size());
  if (o.shard) clips = select_shard(clips, *o.shard);

  // The robot once, fully (URDF, meshes, MJCF), so a bad robot fails the batch up front.
  const RobotConfig config = load_robot_config(o.robot, o.convert.package_paths);
  (void)RobotModel::load(config);
  plan.robot_name = config.name;
  plan.robot_config = absolute_path(config.config_path);
  ExpectedHashes robot;
  robot.robot_config_sha256 = sha256_file(config.config_path);
  robot.urdf_sha256 = sha256_file(config.urdf_path);

  for (BatchClip& c : clips) {
    PlannedClip p;
    const ClipOutputPaths paths = clip_output_paths(o.output_dir, c.output_name, o.convert.formats);
    ExpectedHashes expected = robot;
    expected.options_sha256 = convert_options_sha256(convert_request_for(c, o.convert, paths.stem));
    std::error_code exists_ec;
    if (o.force) {
      p.reason = "--force";
    } else if (!fs::exists(paths.meta, exists_ec)) {
      p.reason = "no meta.json";  // not done yet: no need to hash the input
    } else {
      try {
        expected.source_sha256 = sha256_file(c.input);
      } catch (const InputError&) {
        expected.source_sha256.clear();  // missing or unreadable: never up to date; the worker reports it
      }
      UpToDate u = check_up_to_date(c.input, paths, expected, o.check);
      std::error_code view_ec;
      if (u.up_to_date && o.convert.view && !fs::is_regular_file(paths.view, view_ec)) u = {false, "no viewer page (--view)"};
      p.up_to_date = u.up_to_date;
      p.reason = u.reason;
    }
    p.clip = std::move(c);
    plan.clips.push_back(std::move(p));
  }
  // Largest first: the long clips start early, so the workers finish together.
  std::stable_sort(plan.clips.begin(), plan.clips.end(), [](const PlannedClip& a, const PlannedClip& b) {
    if (a.clip.input_bytes != b.clip.input_bytes) return a.clip.input_bytes > b.clip.input_bytes;
    return a.clip.output_name < b.clip.output_name;
  });
  return plan;
}

BatchSummary run_batch(const BatchOptions& options, const BatchCallbacks& callbacks) {
  BatchOptions o = options;
  if (o.worker_executable.empty()) throw InputError("batch", "no worker executable (the retarget binary) given");
  if (o.jobs < 0) throw InputError("-j", "the number of workers must be >= 1");
  if (o.jobs == 0) o.jobs = available_cpus();
  const auto t0 = Clock::now();
  const std::string started = utc_now();
  const BatchPlan plan = plan_batch(o);

  std::error_code ec;
  fs::create_directories(o.output_dir, ec);
  if (ec) throw InputError(o.output_dir, "cannot create the output folder: " + ec.message());
  const std::string tag = o.shard ? o.shard->file_tag() : std::string();
  const ClipLocks lock((fs::path(o.output_dir) / ".retarget-batch.lock").string(), plan.clips);
  // The batch's own writes (completion markers, summaries) stay inside -o as the workers' do.
  const std::string output_root = resolved_path(fs::absolute(o.output_dir)).string();
  PathConfinement confinement;
  confinement.write_root = output_root;
  const ScopedPathConfinement confined(std::move(confinement));

  BatchSummary summary;
  summary.robot = plan.robot_name;
  summary.robot_config = plan.robot_config;
  summary.input = absolute_path(o.input);
  summary.shard = o.shard ? o.shard->to_string() : "";
  summary.check = o.check;
  summary.convert_options = describe_convert_settings(o.convert, o.check);
  summary.jobs = o.jobs;
  summary.started_utc = started;

  BatchProgress progress;
  progress.total = static_cast<int>(plan.clips.size());
  // Progress in source frames (from the file headers; estimated from the size where unknown).
  std::vector<std::size_t> queue;  // plan indices to run, in order
  std::vector<BatchClip> to_run;
  std::vector<std::int64_t> probed;
  for (std::size_t k = 0; k < plan.clips.size(); ++k)
    if (!plan.clips[k].up_to_date) {
      queue.push_back(k);
      to_run.push_back(plan.clips[k].clip);
      probed.push_back(probe_source_frames(plan.clips[k].clip.input));
    }
  std::vector<double> weight(plan.clips.size(), 0.0);  // by plan index
  {
    const std::vector<double> w = source_frame_weights(to_run, probed);
    for (std::size_t q = 0; q < queue.size(); ++q) weight[queue[q]] = w[q];
  }
  double frames_converted = 0;
  int converted = 0;
  for (const std::size_t k : queue) progress.frames_total += weight[k];

  auto record = [&](ClipResult r) {
    if (r.status == ClipStatus::Ok || r.status == ClipStatus::Skipped) ++progress.done;
    else ++progress.failed;
    if (r.status == ClipStatus::Skipped) ++progress.skipped;
    summary.clips.push_back(std::move(r));
    if (callbacks.on_clip) callbacks.on_clip(summary.clips.back(), progress);
  };

  // Up-to-date clips first: they are done already.
  for (const PlannedClip& p : plan.clips) {
    if (!p.up_to_date) continue;
    ClipResult r = base_result(p.clip);
    const ClipOutputPaths paths = clip_output_paths(o.output_dir, p.clip.output_name, o.convert.formats);
    const std::string problem = read_clip_outputs(r, paths, o.output_dir, o.check);
    r.status = problem.empty() ? ClipStatus::Skipped : ClipStatus::Error;
    r.error = problem;
    record(std::move(r));
  }

  const std::string robot = robot_argument(plan);
  const std::vector<std::string> env = worker_environment();
  std::vector<Running> running;
  std::size_t next = 0;
  std::string stopped;
  Clock::time_point stop_time{}, first_launch{};
  bool killed = false, launched_any = false;
  auto last_progress = Clock::now() - std::chrono::hours(1);
  bool changed = true;

  // ETA: the source frames left (running clips in full) at the source frames per second of wall
  // time converted since the first worker started.
  auto update_rates = [&] {
    if (frames_converted <= 0 || !launched_any) return;
    const double running_s = std::max(1e-3, seconds_since(first_launch));
    progress.eta_s = std::max(0.0, progress.frames_total - progress.frames_done) / (frames_converted / running_s);
    progress.clips_per_min = 60.0 * converted / running_s;
  };

  auto stop = [&](const std::string& why) {
    if (!stopped.empty()) return;
    stopped = why;
    stop_time = Clock::now();
    for (Running& w : running) w.process->terminate(SIGTERM);
  };

  while (true) {
    if (callbacks.stop_requested) {
      const std::string why = callbacks.stop_requested();
      if (!why.empty()) stop(why);
    }
    if (!stopped.empty() && !killed && seconds_since(stop_time) > o.stop_grace_s) {
      for (Running& w : running) w.process->terminate(SIGKILL);
      killed = true;
    }
    // Launch.
    while (stopped.empty() && running.size() < static_cast<std::size_t>(o.jobs) && next < queue.size()) {
      const std::size_t k = queue[next++];
      const BatchClip& clip = plan.clips[k].clip;
      Running w;
      w.index = k;
      w.paths = clip_output_paths(o.output_dir, clip.output_name, o.convert.formats);
      try {
        check_paths_at_launch(clip, w.paths, o.output_dir);
        fs::create_directories(fs::path(w.paths.stem).parent_path(), ec);
        remove_completion_marker(w.paths);  // first: a worker killed from here on leaves the clip to redo
        remove_stale_temporaries(w.paths);
        WorkerLaunch launch;
        launch.argv = {o.worker_executable};
        const std::vector<std::string> args =
            convert_arguments(clip, o.convert, robot, w.paths.stem, o.check ? w.paths.report_dir : "");
        launch.argv.insert(launch.argv.end(), args.begin(), args.end());
        // The worker checks these again where it opens the files (a symlink may change after
        // the check above): the clip and a manifest's profile inside the input root, every
        // output inside -o.
        if (!clip.input_root.empty()) {
          launch.argv.insert(launch.argv.end(), {"--input-root", clip.input_root});
          if (clip.overrides.profile) launch.argv.push_back("--confine-profile");
        }
        launch.argv.insert(launch.argv.end(), {"--output-root", output_root});
        launch.extra_env = env;
        launch.log_path = w.paths.log;
        launch.timeout_s = o.timeout_s;
        launch.memory_limit_bytes = o.memory_limit_bytes;
        w.process = std::make_unique<WorkerProcess>(launch);
      } catch (const std::exception& e) {
        ClipResult r = base_result(clip);
        const bool bad_input = dynamic_cast<const InputError*>(&e) != nullptr;  // a path that escapes
        r.status = bad_input ? ClipStatus::BadInput : ClipStatus::Error;
        r.error = bad_input ? std::string(e.what()) : std::string("cannot start the worker: ") + e.what();
        progress.frames_done += weight[k];
        record(std::move(r));
        if (o.fail_fast) stop("--fail-fast: " + clip.output_name + " failed");
        changed = true;
        continue;
      }
      if (!launched_any) first_launch = Clock::now();
      launched_any = true;
      running.push_back(std::move(w));
      changed = true;
    }
    // Reap.
    for (std::size_t i = 0; i < running.size();) {
      Running& w = running[i];
      if (!w.process->poll()) {
        ++i;
        continue;
      }
      const BatchClip& clip = plan.clips[w.index].clip;
      ClipResult r = finished_result(clip, w.process->exit(), w.paths, o, stopped);
      if (r.status == ClipStatus::Ok || r.status == ClipStatus::CheckFailed) {
        try {
          write_completion_marker(w.paths, o.check);  // last: only now is the clip up to date
        } catch (const std::exception& e) {
          r.status = ClipStatus::Error;
          r.error = e.what();
        }
      }
      progress.frames_done += weight[w.index];
      if (r.status != ClipStatus::Cancelled) {
        frames_converted += weight[w.index];
        ++converted;
      }
      update_rates();  // before record(): the clip's log line shows the ETA with it
      const bool failed = r.status != ClipStatus::Ok;
      running.erase(running.begin() + static_cast<long>(i));
      progress.running = static_cast<int>(running.size());
      record(std::move(r));
      if (failed && o.fail_fast) stop("--fail-fast: " + clip.output_name + " failed");
      changed = true;
    }
    progress.running = static_cast<int>(running.size());
    progress.elapsed_s = seconds_since(t0);
    update_rates();
    if (running.empty() && (next >= queue.size() || !stopped.empty())) break;
    if (callbacks.on_progress && (changed || seconds_since(last_progress) >= 1.0)) {
      callbacks.on_progress(progress);
      last_progress = Clock::now();
      changed = false;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(o.poll_s));
  }
  // Clips never started.
  for (; next < queue.size(); ++next) {
    ClipResult r = base_result(plan.clips[queue[next]].clip);
    r.status = ClipStatus::Cancelled;
    r.error = "not started: " + stopped;
    record(std::move(r));
  }
  progress.running = 0;
  progress.elapsed_s = seconds_since(t0);
  progress.eta_s = 0;
  if (callbacks.on_progress) callbacks.on_progress(progress);

  summary.stopped = stopped;
  summary.wall_s = seconds_since(t0);
  summary.sort_clips();
  write_summary(o.output_dir, summary, tag);
  return summary;
}

}  // namespace rt
