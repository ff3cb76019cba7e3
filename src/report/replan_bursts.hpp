#pragma once
// Groups COM re-planning activations into bursts (private to rt_report): the planner runs every
// 5 ms and often fires on many consecutive ticks, which reads better as one interval than as a
// list of times, in the plots and in the summary alike.

#include <algorithm>
#include <vector>

#include "retarget/sim/dynamics_check.hpp"

namespace rt::report_detail {

/// Activations less than this apart belong to the same burst [s].
inline constexpr double kReplanBurstGapS = 0.05;

struct ReplanBurst {
  double start_s = 0, end_s = 0;  ///< first and last activation
  int count = 0;
  bool case1 = false, case2 = false;  ///< which ReplanEvent kinds occurred
  double max_shift_m = 0;
};

inline std::vector<ReplanBurst> replan_bursts(const std::vector<ReplanRecord>& replans) {
  std::vector<ReplanRecord> sorted = replans;
  std::stable_sort(sorted.begin(), sorted.end(), [](const ReplanRecord& a, const ReplanRecord& b) { return a.t_s < b.t_s; });
  std::vector<ReplanBurst> out;
  for (const ReplanRecord& r : sorted) {
    if (out.empty() || r.t_s - out.back().end_s >= kReplanBurstGapS) out.push_back({r.t_s, r.t_s, 0, false, false, 0});
    ReplanBurst& b = out.back();
    b.end_s = r.t_s;
    ++b.count;
    b.case1 = b.case1 || r.event.kind == 1;
    b.case2 = b.case2 || r.event.kind == 2;
    b.max_shift_m = std::max(b.max_shift_m, r.event.max_shift_m);
  }
  return out;
}

}  // namespace rt::report_detail
