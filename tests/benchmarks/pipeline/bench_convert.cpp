// Benchmark of the conversion pipeline (design.md §7, issue 4): source frames per second of the
// per-frame path (retime, scale, label-contacts, ik, flat-contact) and of the full default pipeline,
// single thread, on a real clip. Usage: bench_convert [robot] [clip] [runs]
// Defaults: g1 and ../shared/data/bvh/cmu_max_131_01_start_walk_stop.bvh, 5 runs.

#include <cstdio>
#include <string>

#include "../bench_util.hpp"
#include "retarget/jobs/convert_job.hpp"
#include "retarget/model/robot_model.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  const std::string robot = argc > 1 ? argv[1] : "g1";
  const std::string clip = argc > 2 ? argv[2] : std::string(RT_SHARED_DATA_DIR) + "/bvh/cmu_max_131_01_start_walk_stop.bvh";
  const int runs = argc > 3 ? std::atoi(argv[3]) : 5;
  try {
    const auto model = RobotModel::load(robot);
    for (const auto& [label, passes] : {std::pair<const char*, const char*>{"per-frame path (retime, scale, label-contacts, ik, flat-contact)",
                                                                           "retime,scale,label-contacts,ik,flat-contact"},
                                        std::pair<const char*, const char*>{"per-frame path + com-replan",
                                                                           "retime,scale,label-contacts,ik,flat-contact,ground,com-replan"},
                                        std::pair<const char*, const char*>{"full default pipeline", ""}}) {
      ConvertRequest request;
      request.clip_path = clip;
      request.passes = passes;
      request.write_outputs = false;
      int frames = 0;
      const auto times = bench::time_runs(runs, [&] { frames = run_convert(request, *model).clip.human.num_frames; });
      const double t = bench::median(times);
      std::printf("%-70s %6d frames  median %8.1f ms  %9.0f source frames/s  (%d runs)\n", label, frames, t * 1e3, frames / t, runs);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_convert: %s\n", e.what());
    return 2;
  }
  return 0;
}
