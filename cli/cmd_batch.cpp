// retarget batch: convert a motion library in parallel worker processes, resumably, with a summary.

#include <CLI/CLI.hpp>

#include <signal.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <climits>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "cli/numeric_option.hpp"
#include "cli/pass_flags.hpp"
#include "retarget/batch/batch_runner.hpp"
#include "retarget/batch/worker_process.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "cli/view_page.hpp"

namespace rt::cli {

namespace {

struct BatchCliOptions {
  BatchOptions batch;
  std::string formats = "csv";
  std::string shard;
  std::string source_units, up_axis, profile;
  double source_fps = 0;
  double memory_limit_mb = static_cast<double>(kDefaultWorkerMemoryLimitBytes) / (1 << 20);
  bool dry_run = false;
  bool quiet = false;
  std::vector<std::string> disabled;  // from --no-<pass>
  std::vector<std::string> enabled;   // from --<pass> (passes not in the default pipeline)
};

// Blocks SIGINT, SIGTERM and SIGHUP while the batch runs; the batch polls them (stop_requested)
// and stops its workers cleanly instead of dying with them half-way. Restores the mask on exit.
class StopSignals {
 public:
  StopSignals() {
    sigemptyset(&set_);
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set_, sig);
    pthread_sigmask(SIG_BLOCK, &set_, &old_);
  }
  ~StopSignals() {
    // Drop signals that arrived after the batch stopped polling, then restore the mask.
    const struct timespec zero {};
    while (sigtimedwait(&set_, nullptr, &zero) > 0) {
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// The name of a pending stop signal ("SIGINT"), or "".
  std::string poll() {
    const struct timespec zero {};
    const int sig = sigtimedwait(&set_, nullptr, &zero);
    if (sig <= 0) return "";
    received_ = sig;
    return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
  }
  int received() const { return received_; }

 private:
  sigset_t set_{}, old_{};
  int received_ = 0;
};

std::string self_executable() {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) throw InternalError("cannot find the retarget executable (/proc/self/exe)");
  return std::string(buf, static_cast<std::size_t>(n));
}

int terminal_width() {
  struct winsize w {};
  if (::ioctl(STDOUT_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 20) return w.ws_col;
  return 100;
}

void print_plan(const BatchPlan& plan, const BatchOptions& o) {
  int up = 0;
  for (const PlannedClip& p : plan.clips) up += p.up_to_date ? 1 : 0;
  std::cout << format("%zu clip(s)", plan.clips.size());
  if (o.shard) std::cout << format(" in shard %s of %d in all", o.shard->to_string().c_str(), plan.total_clips);
  std::cout << format(" for robot %s: %zu to convert, %d up to date\n", plan.robot_name.c_str(), plan.clips.size() - up, up);
  for (const PlannedClip& p : plan.clips)
    std::cout << format("  %-4s %-40s %10llu B  %s  (%s)\n", p.up_to_date ? "skip" : "run", p.clip.output_name.c_str(),
                        static_cast<unsigned long long>(p.clip.input_bytes), p.clip.input.c_str(), p.reason.c_str());
  std::cout << "convert options: " << describe_convert_settings(o.convert, o.check) << "\n";
}

void print_totals(const BatchSummary& s, const std::string& out, const std::string& tag) {
  std::vector<std::string> parts;
  for (ClipStatus st : all_clip_statuses())
    if (const int n = s.count(st)) parts.push_back(format("%d %s", n, clip_status_name(st)));
  std::cout << format("%zu clip(s) in %s: ", s.clips.size(), format_duration(s.wall_s).c_str()) << join(parts, ", ") << "\n";
  if (!s.stopped.empty()) std::cout << "stopped early: " << s.stopped << "\n";
  const SummaryFileNames names = summary_file_names(tag);
  std::cout << "summary: " << out << "/" << names.json << ", " << names.csv << ", " << names.html << "\n";
}

}  // namespace

Command setup_batch(CLI::App& parent) {
  auto o = std::make_shared<BatchCliOptions>();
  BatchOptions& b = o->batch;
  CLI::App* app = parent.add_subcommand(
      "batch", "Convert a folder or manifest of clips in parallel worker processes, resumably, with a summary");
  app->add_option("input", b.input, "Folder of .bvh/.c3d clips (recursive) or a manifest (.yaml/.yml/.csv)")->required();
  app->add_option("--robot", b.robot, "Robot: a name in robots/, a folder or a robot.yaml")->default_val("humanoid25");
  app->add_option("-o,--output", b.output_dir, "Output folder (created when missing)")->required();
  app->add_option("-j,--jobs", b.jobs, "Parallel worker processes (default: the CPUs available)")
      ->check(bounded(1, 1024, ""));
  app->add_flag("--check", b.check, "Run the dynamics check after each conversion; report in <name>.report/");
  app->add_option("--shard", o->shard, "Process only shard I of N (1-based, e.g. 2/8): a deterministic, size-balanced 1/N");
  app->add_flag("--force", b.force, "Redo clips whose outputs are up to date");
  app->add_flag("--fail-fast", b.fail_fast, "Stop at the first failed clip (running workers are cancelled)");
  app->add_option("--timeout", b.timeout_s, "Per-clip wall-clock limit [s]; 0 = none")
      ->default_val(3600)
      ->check(bounded(0, 7 * 24 * 3600, "s"));
  app->add_option("--memory-limit", o->memory_limit_mb, "Per-worker address-space limit [MiB]; 0 = none")
      ->default_val(o->memory_limit_mb)
      ->check(bounded(0, 1 << 24, "MiB"));
  app->add_flag("--allow-outside", b.allow_outside, "Accept manifest clip paths outside the manifest's folder");
  app->add_flag("--dry-run", o->dry_run, "List the clips (of this shard) and whether each is up to date; run nothing");
  app->add_flag("-q,--quiet", o->quiet, "No progress output, only the totals");
  // Convert flags forwarded to every worker (a manifest's per-clip values override them).
  const std::string g = "Convert options (for every clip)";
  app->add_option("--format", o->formats, "Output formats, comma-separated: csv, npz")->default_val("csv")->group(g);
  app->add_option("--npz-layout", b.convert.npz_layout, "NPZ body and joint order: urdf, mjcf:FILE or names:FILE")->group(g);
  app->add_option("--fps", b.convert.fps, "Output frame rate [Hz]")
      ->default_val(30.0)
      ->check(bounded(kMinFrameRate_hz, kMaxOutputFrameRate_hz, "Hz"))
      ->group(g);
  app->add_option("--passes", b.convert.passes, "Pipeline to run instead of the default")->group(g);
  add_pass_flags(app, &o->enabled, &o->disabled);
  app->add_option("--time-scale", b.convert.time_scale, "Play every clip S times slower (S > 1) or faster")
      ->default_val(1.0)
      ->check(bounded(0.05, 20.0, ""))
      ->group(g);
  app->add_option("--max-joint-speed", b.convert.max_joint_speed, "Cap every joint's speed [rad/s] below its URDF limit")
      ->check(bounded(0.01, 1000.0, "rad/s"))
      ->group(g);
  app->add_option("--source-units", o->source_units, "Override the detected source units (m, cm, mm, inch, cmu or a number)")->group(g);
  app->add_option("--source-fps", o->source_fps, "Override the source frame rate [Hz]")
      ->check(bounded(kMinFrameRate_hz, kMaxFrameRate_hz, "Hz"))
      ->group(g);
  app->add_option("--up-axis", o->up_axis, "Override the detected up axis: x, y, z (optionally -y, ...)")->group(g);
  app->add_option("--skeleton-profile,--marker-map", o->profile, "YAML mapping landmarks to joint or marker names")->group(g);
  app->add_flag("--keep-tpose", b.convert.keep_tpose, "Keep a synthetic T-pose at the start")->group(g);
  app->add_flag("--view", b.convert.view,
                "Also write each clip's motion viewer page <name>.html, linked from index.html (see 'retarget view')")
      ->group(g);
  app->add_option("--package-path", b.convert.package_paths, "Extra root folder for package:// URIs (repeatable)")->group(g);
  app->footer(
      "Outputs per clip in OUTDIR: <name>.csv/.npz, <name>.meta.json, <name>.log, <name>.report/ (with --check),\n"
      "<name>.html (with --view: the motion viewer page),\n"
      "<name>.complete (written last: the clip is up to date only with it);\n"
      "plus summary.json, summary.csv and index.html (summary-shard-I-of-N.* and index-shard-I-of-N.html with --shard).\n"
      "Exit status: 0 every clip ok or up to date; 1 some clip failed its check; 2 some clip had bad input or failed\n"
      "otherwise (crashed, timeout, out of memory, ...) -- 2 takes precedence over 1; 128+N when stopped by signal N.");
  return {app, [o, app] {
            BatchOptions& b = o->batch;
            if (app->count("--robot") == 0) std::cerr << "robot: " << b.robot << " (default; pass --robot)\n";
            b.convert.formats = parse_reference_formats(o->formats);
            // A layout file relative to here must still be found by the workers.
            if (const auto colon = b.convert.npz_layout.find(':'); colon != std::string::npos)
              b.convert.npz_layout = b.convert.npz_layout.substr(0, colon + 1) +
                                     std::filesystem::absolute(b.convert.npz_layout.substr(colon + 1)).lexically_normal().string();
            b.convert.disabled_passes = o->disabled;
            b.convert.enabled_passes = o->enabled;
            if (!o->source_units.empty()) b.convert.source_units = o->source_units;
            if (o->source_fps > 0) b.convert.source_fps = o->source_fps;
            if (!o->up_axis.empty()) b.convert.up_axis = o->up_axis;
            if (!o->profile.empty()) b.convert.profile = std::filesystem::absolute(o->profile).lexically_normal().string();
            for (std::string& p : b.convert.package_paths) p = std::filesystem::absolute(p).lexically_normal().string();
            if (!o->shard.empty()) b.shard = parse_shard(o->shard);
            b.memory_limit_bytes = static_cast<std::uint64_t>(o->memory_limit_mb * (1 << 20));
            b.worker_executable = self_executable();
            if (b.convert.view) require_three_js(viewer_options());  // once here, not once per clip
            if (o->dry_run) {
              print_plan(plan_batch(b), b);
              return kExitOk;
            }
            const bool tty = ::isatty(STDOUT_FILENO) == 1;
            const int total_width = tty ? terminal_width() : 0;
            StopSignals signals;
            BatchCallbacks cb;
            cb.stop_requested = [&signals] { return signals.poll(); };
            int finished = 0;
            if (!o->quiet) {
              cb.on_clip = [&](const ClipResult& c, const BatchProgress& p) {
                ++finished;
                if (tty && c.status == ClipStatus::Ok) return;
                if (tty && c.status == ClipStatus::Skipped) return;
                // A terminal has the ETA in the live bar; a log gets it on every clip's line.
                std::cout << (tty ? "\r\033[K" + format_clip_line(c, finished, p.total) : format_clip_log_line(c, p)) << "\n"
                          << std::flush;
              };
              if (tty)
                cb.on_progress = [&](const BatchProgress& p) {
                  std::cout << "\r\033[K" << format_progress_bar(p, total_width - 1) << std::flush;
                };
            }
            const BatchSummary s = run_batch(b, cb);
            if (tty && !o->quiet) std::cout << "\n";
            print_totals(s, b.output_dir, b.shard ? b.shard->file_tag() : "");
            if (signals.received() > 0) return 128 + signals.received();
            return batch_exit_status(s);
          }};
}

}  // namespace rt::cli
