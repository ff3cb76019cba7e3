#pragma once
/// Wall time of a pass's stages [ms], for its -v statistics: each lap adds the time since the
/// previous lap (or the timer's start) to one stage's total, so a loop's stages sum over rounds.

#include <chrono>

namespace rt {

class LapTimer {
 public:
  /// Adds the time since the last lap to `total_ms`.
  void lap(double& total_ms) {
    const auto now = std::chrono::steady_clock::now();
    total_ms += std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace rt
