// C3D load + landmark extraction throughput (issue 3 target: >= 50 MB/s).
//
//   c3d_benchmark [--runs N] [FILE.c3d | FOLDER]...
//
// Without paths it uses every .c3d in the shared data folder. For each file it times, over N runs
// (default 9), (a) reading + decoding the file (read_c3d: header, parameters, point data, analog
// skipped) and (b) the whole load_c3d_motion (decode, marker-set recognition, rigid-cluster gap
// filling, joint centres, up axis, trimming, gap interpolation, normalisation), and prints the
// medians as frames/s and MB/s. Files that cannot become a motion (the unlabeled PhaseSpace
// sample) are timed for decoding only. The total line divides the summed frames and bytes by the
// summed medians. Single-threaded; build in Release.

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/c3d/c3d_reader.hpp"
#include "../bench_util.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/c3d/c3d_motion.hpp"

int main(int argc, char** argv) {
  const rt::bench::FileBenchArgs args =
      rt::bench::parse_file_bench_args(argc, argv, ".c3d", std::string(RT_SHARED_DATA_DIR) + "/c3d");
  const int runs = args.runs;
  const std::vector<std::string>& files = args.files;
  if (files.empty()) {
    std::fprintf(stderr, "no .c3d files found (shared data absent?): pass files or folders\n");
    return 1;
  }

  std::printf("C3D decode and load + landmark extraction, median of %d runs per file\n", runs);
  std::printf("%-52s %6s %6s | %10s %8s | %10s %8s\n", "file", "frames", "MB", "decode f/s", "MB/s", "load f/s", "MB/s");
  double decode_frames = 0, decode_mb = 0, decode_s = 0;
  double load_frames = 0, load_mb = 0, load_s = 0;
  for (const std::string& path : files) {
    const std::string name = std::filesystem::path(path).filename().string();
    try {
      const double mb = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
      int frames = 0;
      const double d = rt::bench::median_seconds(runs, [&] { frames = rt::c3d::read_c3d(path).points.num_frames; });
      decode_frames += frames;
      decode_mb += mb;
      decode_s += d;
      double l = 0;
      std::string load_error;
      try {
        (void)rt::load_c3d_motion(path, rt::MotionLoadOptions{});
        l = rt::bench::median_seconds(runs, [&] { (void)rt::load_c3d_motion(path, rt::MotionLoadOptions{}); });
        load_frames += frames;
        load_mb += mb;
        load_s += l;
      } catch (const rt::InputError& e) {
        load_error = "no motion: marker set not recognised";
      }
      if (load_error.empty())
        std::printf("%-52s %6d %6.3f | %10.0f %8.1f | %10.0f %8.1f\n", name.c_str(), frames, mb, frames / d, mb / d,
                    frames / l, mb / l);
      else
        std::printf("%-52s %6d %6.3f | %10.0f %8.1f | %s\n", name.c_str(), frames, mb, frames / d, mb / d,
                    load_error.c_str());
    } catch (const rt::InputError& e) {
      std::printf("%-52s error: %s\n", name.c_str(), e.what());
    }
  }
  std::printf("%-52s %6.0f %6.3f | %10.0f %8.1f | %10.0f %8.1f\n", "TOTAL (load: files that give a motion)", decode_frames,
              decode_mb, decode_frames / decode_s, decode_mb / decode_s, load_frames / load_s, load_mb / load_s);
  return 0;
}
