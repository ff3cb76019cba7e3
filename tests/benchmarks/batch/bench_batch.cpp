// Benchmark of `retarget batch` (design.md §7): wall time with -j 1 and -j 2 on a folder of clips
// (default: the shared BVH set on G1), the speed-up, and peak memory per worker.
//
//   bench_batch [--input DIR] [--robot ROBOT] [--runs N] [--retarget PATH] [-- EXTRA BATCH FLAGS]
//
// Each configuration runs N times (after one warm-up run of -j 1 that fills the page cache) with
// --force into a scratch folder; the driver prints every run, the medians, the speed-up of the
// medians, the load average before and after (other work on the machine skews the numbers: run it
// when the machine is quiet), and the largest per-worker peak RSS (getrusage ru_maxrss of each
// worker, from summary.json: the same number `/usr/bin/time -v` reports as "Maximum resident set
// size" for a single convert).

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "retarget/batch/batch_summary.hpp"
#include "retarget/batch/worker_process.hpp"
#include "retarget/core/strings.hpp"

namespace {

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return 0;
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct RunResult {
  double wall_s = 0;
  double worker_peak_mb = 0;
  double worker_time_sum_s = 0;
  int ok = 0, clips = 0;
};

RunResult run_batch(const std::string& retarget, const std::string& input, const std::string& robot, int jobs,
                    const std::string& out, const std::vector<std::string>& extra) {
  rt::WorkerLaunch l;
  l.argv = {retarget, "batch", input, "--robot", robot, "-o", out, "-j", std::to_string(jobs), "--force", "-q"};
  l.argv.insert(l.argv.end(), extra.begin(), extra.end());
  l.log_path = out + ".log";
  const auto t0 = std::chrono::steady_clock::now();
  const rt::WorkerExit x = rt::run_worker(l);
  RunResult r;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!x.exited || x.exit_code > 2) {
    std::cerr << "batch failed (exit " << x.exit_code << ", signal " << x.signal << "); see " << l.log_path << "\n";
    std::exit(1);
  }
  const rt::BatchSummary s = rt::read_summary(out + "/summary.json");
  for (const rt::ClipResult& c : s.clips) {
    r.worker_peak_mb = std::max(r.worker_peak_mb, c.peak_rss_mb);
    r.worker_time_sum_s += c.time_s;
    r.ok += c.status == rt::ClipStatus::Ok || c.status == rt::ClipStatus::CheckFailed;
  }
  r.clips = static_cast<int>(s.clips.size());
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::string input = std::string(RT_SHARED_DATA_DIR) + "/bvh";
  std::string robot = "g1";
  std::string retarget = std::string(RT_BINARY_DIR) + "/retarget";
  int runs = 3;
  std::vector<std::string> extra;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--input") input = next();
    else if (a == "--robot") robot = next();
    else if (a == "--runs") runs = std::max(1, std::atoi(next().c_str()));
    else if (a == "--retarget") retarget = next();
    else if (a == "--") {
      extra.assign(argv + i + 1, argv + argc);
      break;
    } else {
      std::cerr << "usage: bench_batch [--input DIR] [--robot ROBOT] [--runs N] [--retarget PATH] [-- FLAGS]\n";
      return 2;
    }
  }
  if (!std::filesystem::exists(input)) {
    std::cout << "input not found: " << input << " (the shared test data is absent); nothing to measure\n";
    return 0;
  }
  char tmpl[] = "/tmp/bench_batch.XXXXXX";
  const char* dir = ::mkdtemp(tmpl);
  if (!dir) return 1;
  const std::string scratch = dir;

  std::cout << "retarget batch " << input << " --robot " << robot << " (" << rt::join(extra, " ") << "), " << runs
            << " runs per setting, " << rt::available_cpus() << " CPUs available\n";
  std::cout << "load average before: " << load_average() << "\n";
  run_batch(retarget, input, robot, 1, scratch + "/warmup", extra);  // page cache, robot meshes
  std::vector<double> wall[2];
  double peak_mb = 0, worker_sum = 0;
  int clips = 0, ok = 0;
  for (int r = 0; r < runs; ++r)
    for (int j = 1; j <= 2; ++j) {  // interleaved, so slow drifts in machine load hit both alike
      const RunResult x = run_batch(retarget, input, robot, j, scratch + rt::format("/j%d_run%d", j, r), extra);
      wall[j - 1].push_back(x.wall_s);
      peak_mb = std::max(peak_mb, x.worker_peak_mb);
      worker_sum = x.worker_time_sum_s;
      clips = x.clips;
      ok = x.ok;
      std::cout << rt::format("  run %d  -j %d  %7.2f s  (%d/%d clips converted; sum of worker times %.1f s; load %s)\n", r + 1,
                              j, x.wall_s, x.ok, x.clips, x.worker_time_sum_s, load_average().c_str());
    }
  const double m1 = median(wall[0]), m2 = median(wall[1]);
  std::cout << rt::format("median wall time: -j 1 %.2f s, -j 2 %.2f s; speed-up %.2fx (target >= 1.8x)\n", m1, m2, m1 / m2);
  std::cout << rt::format("clips: %d (%d converted), sum of worker times in the last run %.1f s\n", clips, ok, worker_sum);
  std::cout << rt::format("peak resident memory of any worker: %.1f MiB (target <= 300 MB)\n", peak_mb);
  std::cout << "load average after: " << load_average() << "\n";
  std::filesystem::remove_all(scratch);
  return 0;
}
