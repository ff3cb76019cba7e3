// BVH load + landmark extraction throughput (issue 3 target: >= 20,000 frames/s).
//
//   bvh_benchmark [--runs N] [FILE.bvh | FOLDER]...
//
// Without paths it uses every .bvh in the shared data folder. For each clip it times, over N runs
// (default 9), (a) reading + parsing the text (read_bvh) and (b) the whole load_bvh_motion
// (read, recognise, forward kinematics, landmarks, units / up axis / T-pose detection,
// normalisation), and prints the medians as frames/s and MB/s. The total line divides the summed
// frames and bytes by the summed medians. Single-threaded; build in Release.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/bvh/bvh_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <class F>
double median_seconds(int runs, F&& work) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(std::move(t));
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 9;
  std::vector<std::string> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else inputs.push_back(a);
  }
  if (inputs.empty()) inputs.push_back(std::string(RT_SHARED_DATA_DIR) + "/bvh");
  std::vector<std::string> files;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (std::filesystem::is_directory(in, ec)) {
      for (const auto& e : std::filesystem::directory_iterator(in))
        if (e.path().extension() == ".bvh") files.push_back(e.path().string());
    } else {
      files.push_back(in);
    }
  }
  std::sort(files.begin(), files.end());
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
      const double parse_s = median_seconds(runs, [&] { frames = rt::read_bvh(path).num_frames; });
      const double load_s = median_seconds(runs, [&] { (void)rt::load_bvh_motion(path); });
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
