#pragma once
// Helpers of the jobs tests that run over ../shared/data: one loaded model per robot for the whole
// test program, and gtest-safe case names from "robot" + "clip path".

#include <cctype>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"

namespace rt::test {

inline const RobotModel& shared_robot(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<RobotModel>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[name];
  if (!slot) slot = RobotModel::load(source_path("robots/" + name));
  return *slot;
}

/// "g1" + "bvh/walk.bvh" -> "g1_bvh_walk_bvh" (gtest names allow only [A-Za-z0-9_]).
inline std::string case_name(const std::string& robot, const std::string& clip) {
  std::string n = robot + "_" + clip;
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
}

}  // namespace rt::test
