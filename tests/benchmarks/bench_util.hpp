#pragma once
/// Shared helpers of the benchmark programs: repeated timing, medians, and the
/// `[--runs N] [FILE | FOLDER]...` command line of the file-reading benchmarks.

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <system_error>
#include <vector>

namespace rt::bench {

/// Runs `f` `runs` times after one warm-up run; returns the wall seconds of each timed run.
inline std::vector<double> time_runs(int runs, const std::function<void()>& f) {
  f();
  std::vector<double> out;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    out.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return out;
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// Median wall seconds of `runs` runs of `f` (no warm-up run).
inline double median_seconds(int runs, const std::function<void()>& f) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(std::move(t));
}

/// What a file-reading benchmark was asked to read.
struct FileBenchArgs {
  int runs = 9;
  std::vector<std::string> files;  ///< sorted
};

/// Parses `[--runs N] [FILE | FOLDER]...`: folders contribute their files ending in `extension`
/// (not recursive); without paths, `default_folder` is used.
inline FileBenchArgs parse_file_bench_args(int argc, char** argv, const std::string& extension,
                                           const std::string& default_folder) {
  FileBenchArgs a;
  std::vector<std::string> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--runs" && i + 1 < argc) a.runs = std::max(1, std::atoi(argv[++i]));
    else inputs.push_back(arg);
  }
  if (inputs.empty()) inputs.push_back(default_folder);
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (std::filesystem::is_directory(in, ec)) {
      for (const auto& e : std::filesystem::directory_iterator(in))
        if (e.path().extension() == extension) a.files.push_back(e.path().string());
    } else {
      a.files.push_back(in);
    }
  }
  std::sort(a.files.begin(), a.files.end());
  return a;
}

}  // namespace rt::bench
