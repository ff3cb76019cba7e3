#pragma once
/// Robot models shared by the tests of one executable: loading G1 (meshes) costs ~0.3 s in Release
/// and ~10 s under the sanitizers, so each robot is loaded once. Models are immutable.

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "retarget/model/robot_model.hpp"

namespace rt::test {

/// RobotModel::load(robot), loaded on first use and kept for the process.
inline const RobotModel& cached_robot(const std::string& robot) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<RobotModel>> models;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = models[robot];
  if (!slot) slot = RobotModel::load(robot);
  return *slot;
}

}  // namespace rt::test
