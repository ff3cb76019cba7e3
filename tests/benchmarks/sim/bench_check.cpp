// Benchmark of the dynamics check (design.md §7, issues 5, 6 and 15): real-time factor of the
// closed loop (1 ms simulation, 2 ms control) per robot, single thread: the walking controller on
// the synthetic walk (also at 1 ms control), the paper controller standing, and the cost of the
// paper's online COM re-planner while it is active (foot-lift reference: from t = 0.5 s), and the
// walking controller's whole-clip balance plan (its mapping's first stage, before the simulation)
// on a long clip: a 122 s synthetic walk (sim/balance_plan.hpp; the sparse QP of balance/sparse_qp.hpp).
// Usage: bench_check [runs] [robot ...]   (defaults: 5 runs; humanoid25 g1)

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../bench_util.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/reference/synthetic_references.hpp"
#include "retarget/sim/balance_plan.hpp"
#include "retarget/sim/dynamics_check.hpp"
#include "retarget/sim/reference_signal.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  const int runs = argc > 1 ? std::atoi(argv[1]) : 5;
  std::vector<std::string> robots;
  for (int i = 2; i < argc; ++i) robots.push_back(argv[i]);
  if (robots.empty()) robots = {"humanoid25", "g1"};
  try {
    for (const std::string& name : robots) {
      const auto model = RobotModel::load(name);
      // The walking controller (the default) on the synthetic walk, at control periods of 2 ms (the
      // default) and 1 ms.
      const Reference walk = walk_reference(*model);
      for (const double period : {0.002, 0.001}) {
        DynamicsCheckOptions w = default_check_options(*model);
        w.control_period_s = period;
        double walk_sim_s = 0;
        bool passed = false;
        auto times = bench::time_runs(runs, [&] {
          const DynamicsCheckResult r = run_dynamics_check(*model, walk, w);
          walk_sim_s = r.simulated_s + w.settle_s;
          passed = r.passed;
        });
        const double fastest = *std::min_element(times.begin(), times.end());
        std::printf("%-12s walking controller, synthetic walk %.1f s, control %.0f ms: median %.3f s wall, real-time factor "
                    "%.1fx (fastest run %.1fx; %d runs; %s)\n",
                    name.c_str(), walk.duration_s(), period * 1e3, bench::median(times), walk_sim_s / bench::median(times),
                    walk_sim_s / fastest, runs, passed ? "passed" : "FAILED");
      }
      {
        WalkOptions long_walk;
        long_walk.steps = 100;  // 1 s standing, 100 steps of 1.2 s, 1 s standing
        long_walk.step_s = 1.2;
        long_walk.double_support_s = 0.2;
        const Reference ref = walk_reference(*model, long_walk);
        RobotData data(*model);
        const ReferenceSignal signal(*model, data, ref);
        const DynamicsCheckOptions d = default_check_options(*model);
        BalancePlanOptions po = d.walking.plan;  // as the walking controller sets it up
        po.lead_in_s = d.settle_s;
        po.ankle_reach = d.walking.ankle_reach;
        int samples = 0;
        auto times = bench::time_runs(runs, [&] { samples = plan_reference_balance(*model, data, signal, po).size(); });
        std::printf("%-12s balance plan of a %.0f s walk (%d samples of 10 ms): median %.3f s wall (fastest %.3f s; %d runs)\n",
                    name.c_str(), ref.duration_s(), samples, bench::median(times), *std::min_element(times.begin(), times.end()),
                    runs);
      }
      DynamicsCheckOptions o = default_check_options(*model);
      o.controller = CheckControllerKind::Paper;  // the paper controller's figures below
      const Reference standing = constant_reference(*model, model->standing_q(), 10.0, 30.0);
      double sim_s = 0;
      auto rtf_times = bench::time_runs(runs, [&] {
        const DynamicsCheckResult r = run_dynamics_check(*model, standing, o);
        sim_s = r.simulated_s + o.settle_s;
      });
      // The fastest run too: on a shared machine the slow ones measure the neighbours.
      const double fastest = *std::min_element(rtf_times.begin(), rtf_times.end());
      std::printf("%-12s standing 10 s: median %.3f s wall, real-time factor %.1fx (fastest run %.1fx; %d runs)\n",
                  name.c_str(), bench::median(rtf_times), sim_s / bench::median(rtf_times), sim_s / fastest, runs);

      // Re-planner cost while it is active (foot lift, from the first activation at ~0.5 s): planner
      // time over the rest of the control cycle, summed over the active span.
      const Reference lift = foot_lift_reference(*model);
      std::vector<double> overhead;
      for (int i = 0; i < runs; ++i) {
        const DynamicsCheckResult r = run_dynamics_check(*model, lift, o);
        if (r.active_cycles > 0) overhead.push_back(r.planner_wall_s / (r.active_loop_wall_s - r.planner_wall_s));
      }
      std::printf("%-12s online COM re-planner while active (foot lift): +%.1f%% per control cycle (median of %zu runs)\n",
                  name.c_str(), 100.0 * bench::median(overhead), overhead.size());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_check: %s\n", e.what());
    return 2;
  }
  return 0;
}
