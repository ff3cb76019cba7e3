#pragma once
/// Shared helpers of the benchmark programs: repeated timing and medians.

#include <algorithm>
#include <chrono>
#include <functional>
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

}  // namespace rt::bench
