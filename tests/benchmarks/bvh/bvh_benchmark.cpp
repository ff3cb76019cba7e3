// BVH load + landmark extraction throughput (issue 3 target: >= 20,000 frames/s).
//
//   bvh_benchmark [--runs N] [FILE.bvh | FOLDER]...
//
// Without paths it uses every .bvh in the shared data folder. For each clip it times, over N runs
// (default 9), (a) reading + parsing the text (read_bvh) and (b) the whole load_bvh_motion
// (read, recognise, forward kinematics, landmarks, units / up axis / T-pose detection,
// normalisation), and prints the medians as frames/s and MB/s. The total line divides the summed
// frames and bytes by the summed medians. Single-threaded; build in Release.

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/bvh/bvh_reader.hpp"
#include "../bench_util.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"

int main(int argc, char** argv) {
  const rt::bench::FileBenchArgs args =
      rt::bench::parse_file_bench_args(argc, argv, ".bvh", std::string(RT_SHARED_DATA_DIR) + "/bvh");
  const int runs = args.runs;
  const std::vector<std::string>& files = args.files;
  if (files.empty()) {
    std::fprintf(stderr, "no .bvh files found (shared data absent?): pass files or folders\n");
    return 1;
  }

  std::printf("BVH load + landmark extraction, median of %d runs per clip\n", runs);
  std::printf("%-46s %7s %8s | %10s %8s | %10s %8s\n", "clip", "frames", "MB", "parse f/s", "MB/s", "load f/s", "MB/s");
  double total_frames = 0, total_mb = 0, total_parse_s = 0, total_load_s = 0;
  for (const std::string& path : files) {
    try {
      const double mb = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
      int frames = 0;
      const double parse_s = rt::bench::median_seconds(runs, [&] { frames = rt::read_bvh(path).num_frames; });
      const double load_s = rt::bench::median_seconds(runs, [&] { (void)rt::load_bvh_motion(path); });
      total_frames += frames;
      total_mb += mb;
      total_parse_s += parse_s;
      total_load_s += load_s;
      std::printf("%-46s %7d %8.3f | %10.0f %8.1f | %10.0f %8.1f\n", std::filesystem::path(path).filename().c_str(), frames,
                  mb, frames / parse_s, mb / parse_s, frames / load_s, mb / load_s);
    } catch (const rt::InputError& e) {
      std::printf("%-46s error: %s\n", std::filesystem::path(path).filename().c_str(), e.what());
    }
  }
  std::printf("%-46s %7.0f %8.3f | %10.0f %8.1f | %10.0f %8.1f\n", "TOTAL", total_frames, total_mb,
              total_frames / total_parse_s, total_mb / total_parse_s, total_frames / total_load_s, total_mb / total_load_s);
  return 0;
}
