#pragma once
/// Helpers shared by the batch tests: scratch files, the example clips, the retarget binary and
/// the fake worker, and batch options that keep the tests fast.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "retarget/batch/batch_runner.hpp"
#include "support/test_paths.hpp"

namespace rt::test {

inline void write_text(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Copies examples/clips/<clip>.bvh to `dest` (project-authored clips, so copying is fine).
inline void copy_example(const std::string& clip, const std::string& dest) {
  std::filesystem::create_directories(std::filesystem::path(dest).parent_path());
  std::filesystem::copy_file(source_path("examples/clips/" + clip + ".bvh"), dest,
                             std::filesystem::copy_options::overwrite_existing);
}

/// The `retarget` binary of this build.
inline std::string retarget_binary() { return std::string(RT_BINARY_DIR) + "/retarget"; }
/// The fake worker (fake_worker.cpp).
inline std::string fake_worker() { return RT_FAKE_WORKER; }

/// Options for a quick batch on humanoid25: the refine pass off (tests of the batch machinery, not
/// of the optimiser), two workers, the fake worker in front of the real binary.
inline BatchOptions quick_batch(const std::string& input, const std::string& out) {
  BatchOptions o;
  o.input = input;
  o.output_dir = out;
  o.robot = "humanoid25";
  o.jobs = 2;
  o.convert.disabled_passes = {"refine"};
  o.worker_executable = fake_worker();
  o.timeout_s = 60;
  o.memory_limit_bytes = 0;
  o.poll_s = 0.005;
  return o;
}

inline const ClipResult* find_clip(const BatchSummary& s, const std::string& name) {
  for (const ClipResult& c : s.clips)
    if (c.name == name) return &c;
  return nullptr;
}

}  // namespace rt::test
