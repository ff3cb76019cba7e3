// Benchmark of the conversion pipeline (design.md §7, issues 4 and 13): source frames per second of
// the per-frame path (retime, scale, label-contacts, ik, resample), of that path with com-replan,
// of the full default pipeline (with com-plan, issue 14) and of it without com-plan, single thread, on real clips; and the
// full pipeline's cost as a multiple of the per-frame path measured in the same run (issue 13: at most 10x).
//
//   bench_convert [robot] [runs] [clip ...]
//
// Defaults: g1, 5 runs, the CMU walk (120 fps, 994 frames) and the LAFAN1 dance
// (30 fps, 3945 frames) from ../shared/data/bvh (clips that are absent are skipped).

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "../bench_util.hpp"
#include "retarget/jobs/convert_job.hpp"
#include "retarget/model/robot_model.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  const std::string robot = argc > 1 ? argv[1] : "g1";
  const int runs = argc > 2 ? std::atoi(argv[2]) : 5;
  std::vector<std::string> clips;
  for (int i = 3; i < argc; ++i) clips.emplace_back(argv[i]);
  if (clips.empty())
    for (const char* name : {"cmu_max_131_01_start_walk_stop.bvh", "lafan1_dance1_subject2.bvh"}) {
      const std::string path = std::string(RT_SHARED_DATA_DIR) + "/bvh/" + name;
      if (std::filesystem::exists(path)) clips.push_back(path);
    }
  if (runs < 1 || clips.empty()) {
    std::fprintf(stderr, "bench_convert: usage: bench_convert [robot] [runs >= 1] [clip ...] (no clip found)\n");
    return 2;
  }
  try {
    const auto model = RobotModel::load(robot);
    for (const std::string& clip : clips) {
      std::printf("%s on %s\n", std::filesystem::path(clip).filename().c_str(), robot.c_str());
      double per_frame_s = 0;
      for (const auto& [label, passes] : {std::pair<const char*, const char*>{"per-frame path (retime, scale, label-contacts, ik, resample)",
                                                                             "retime,scale,label-contacts,ik,resample"},
                                          std::pair<const char*, const char*>{"per-frame path + flat-contact, ground, com-replan",
                                                                             "retime,scale,label-contacts,ik,flat-contact,ground,com-replan,resample"},
                                          std::pair<const char*, const char*>{"default pipeline without com-plan",
                                                                             "retime,scale,label-contacts,ik,flat-contact,refine,ground,resample"},
                                          std::pair<const char*, const char*>{"full default pipeline (with com-plan)", ""}}) {
        ConvertRequest request;
        request.clip_path = clip;
        request.passes = passes;
        request.write_outputs = false;
        int frames = 0;
        std::vector<double> com_plan_s;  // the com-plan pass's own time per run (its record)
        const auto times = bench::time_runs(runs, [&] {
          const ConvertResult r = run_convert(request, *model);
          frames = r.clip.human.num_frames;
          for (const PassRecord& p : r.passes)
            if (p.name == "com-plan") com_plan_s.push_back(p.time_ms * 1e-3);
        });
        const double t = bench::median(times);
        if (per_frame_s == 0) per_frame_s = t;
        std::printf("  %-58s %6d frames  median %8.1f ms  %9.0f source frames/s  %5.1fx the per-frame path  (%d runs)\n", label,
                    frames, t * 1e3, frames / t, t / per_frame_s, runs);
        if (!com_plan_s.empty()) {
          const double c = bench::median(com_plan_s);
          std::printf("  %-58s %6d frames  median %8.1f ms  %9.0f source frames/s  %5.1fx the per-frame path  (%d runs)\n",
                      "  of which the com-plan pass (issue 14's target: 2000/s)", frames, c * 1e3, frames / c, c / per_frame_s, runs);
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_convert: %s\n", e.what());
    return 2;
  }
  return 0;
}
