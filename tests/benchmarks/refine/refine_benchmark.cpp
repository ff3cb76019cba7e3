// Refine pass throughput (issue 4 target: >= 500 source frames/s for G1 with the CMU walk clip;
// issue 13 sets the targets for the whole pipeline, bench_convert measures those).
//
//   bench_refine [--runs N] [--robot ROBOT] [--options 'k=v,...'] [CLIP.bvh ...]
//
// Defaults: robot g1, the clip /work/shared/data/bvh/cmu_max_131_01_start_walk_stop.bvh (120 Hz,
// 994 frames), 7 runs. The per-frame passes (scale, label-contacts, ik, flat-contact) run once;
// then the refine pass runs N times on copies of that clip, and the median wall time of the pass is
// printed as source frames/s, with the pass's statistics of the last run and the quality metrics
// (design.md §6) after refine. Single-threaded; build in Release.

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/motion/load_motion.hpp"
#include "retarget/passes/quality.hpp"
#include "retarget/passes/registry.hpp"

namespace {

// Process CPU time [s]: on a shared machine it varies less than wall time (the pass is single-threaded).
double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 7;
  std::string robot = "g1", options;
  std::vector<std::string> clips;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--robot" && i + 1 < argc) robot = argv[++i];
    else if (a == "--options" && i + 1 < argc) options = argv[++i];
    else clips.push_back(a);
  }
  if (clips.empty()) clips.push_back(std::string(RT_SHARED_DATA_DIR) + "/bvh/cmu_max_131_01_start_walk_stop.bvh");
  try {
    if (robot.find('/') == std::string::npos) robot = std::string(RT_SOURCE_DIR) + "/robots/" + robot;
    const auto model = rt::RobotModel::load(robot);
    rt::RobotData data(*model);
    const rt::Pipeline before = rt::Pipeline::parse("scale,label-contacts,ik,flat-contact", rt::builtin_passes());
    const rt::Pipeline refine = rt::Pipeline::parse(options.empty() ? "refine" : "refine{" + options + "}", rt::builtin_passes());
    std::printf("refine pass, robot %s, median of %d runs\n", model->name().c_str(), runs);
    for (const std::string& path : clips) {
      rt::Clip clip;
      clip.name = path;
      clip.human = rt::load_motion(path);
      (void)before.run(clip, model.get(), &data);
      std::vector<double> seconds, cpu_seconds;
      std::vector<rt::PassRecord> records;
      rt::Clip refined;
      for (int r = 0; r < runs; ++r) {
        refined = clip;
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = cpu_now();
        records = refine.run(refined, model.get(), &data);
        cpu_seconds.push_back(cpu_now() - c0);
        seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      const int T = clip.motion.num_frames();
      const double s = median(seconds);
      const double cpu = median(cpu_seconds);
      std::printf("%s: %d frames at %g Hz: refine %.1f ms median wall (min %.1f, max %.1f) = %.0f source frames/s; "
                  "CPU %.1f ms = %.0f source frames/s\n",
                  path.c_str(), T, clip.motion.fps, 1e3 * s, 1e3 * *std::min_element(seconds.begin(), seconds.end()),
                  1e3 * *std::max_element(seconds.begin(), seconds.end()), T / s, 1e3 * cpu, T / cpu);
      for (const rt::Statistic& st : records.front().statistics.items())
        std::printf("    %-28s %12.6g %s\n", st.name.c_str(), st.value, st.unit.c_str());
      const rt::QualityMetrics q = rt::compute_quality(*model, data, refined);
      std::printf("    quality after refine: landmark error median %.4f m p95 %.4f m, stance skating p95 %.4f m max %.4f m,\n"
                  "    yaw drift max %.2f deg, lowest point %.4f m (%s), position violations %d, velocity violations %d\n"
                  "    (max ratio %.2f), jitter %.1f (per-frame IK %.1f) rad/s^3\n",
                  q.landmark_error_median_m, q.landmark_error_p95_m, q.foot_skating_p95_m, q.foot_skating_max_m,
                  q.stance_yaw_drift_max_deg, q.lowest_point_m, q.lowest_link.c_str(), q.position_limit_violations,
                  q.velocity_limit_violations, q.max_velocity_ratio, q.jitter_rad_s3, q.jitter_per_frame_ik_rad_s3);
      for (const rt::Diagnostic& d : refined.diagnostics.items()) std::printf("    %s\n", d.to_string().c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_refine: %s\n", e.what());
    return 1;
  }
  return 0;
}
