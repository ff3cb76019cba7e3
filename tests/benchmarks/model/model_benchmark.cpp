// Model benchmark (plain timed driver, medians of several repetitions):
//   load      RobotModel::load (robot.yaml + URDF + meshes -> MJCF -> mjModel)
//   step      mj_step of the standing hold (joint PD through the motors, 1 ms step, 2 s simulated)
//   dyn       one controller query set: update_dynamics + mass_matrix + bias_forces + com_jacobian
//             + link_jacobian and link_jdot_v of both soles
// Robots whose URDF is not available (shared data absent) are skipped.

#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/standing_hold.hpp"

using namespace rt;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void run(const std::string& robot) {
  constexpr int kRepetitions = 5;
  std::vector<double> load_s;
  std::unique_ptr<RobotModel> model;
  try {
    for (int i = 0; i < kRepetitions; ++i) {
      const auto t0 = Clock::now();
      model = RobotModel::load(robot);
      load_s.push_back(seconds_since(t0));
    }
  } catch (const InputError& e) {
    std::printf("%-12s skipped: %s\n", robot.c_str(), e.what());
    return;
  }

  std::vector<double> step_s;
  StandingHoldResult hold;
  for (int i = 0; i < kRepetitions; ++i) {
    const auto t0 = Clock::now();
    hold = simulate_standing_hold(*model);
    step_s.push_back(seconds_since(t0) / hold.steps);
  }

  RobotData data(*model);
  const VecX q = model->standing_q();
  const VecX v = VecX::Constant(model->nv(), 0.1);
  std::vector<double> dyn_s;
  double sink = 0;
  for (int i = 0; i < kRepetitions; ++i) {
    constexpr int kCalls = 2000;
    const auto t0 = Clock::now();
    for (int c = 0; c < kCalls; ++c) {
      update_dynamics(*model, data, q, v);
      sink += mass_matrix(*model, data)(0, 0) + bias_forces(*model, data)[0] + com_jacobian(*model, data)(0, 0);
      for (const Sole& s : model->soles()) {
        sink += link_jacobian(*model, data, s.link, s.p_L_center)(0, 0);
        sink += link_jdot_v(*model, data, s.link, s.p_L_center)[0];
      }
    }
    dyn_s.push_back(seconds_since(t0) / kCalls);
  }
  const double step = median(step_s);
  const double dt = model->mj()->opt.timestep;
  std::printf("%-12s nq %3d  nv %3d  mass %7.3f kg  com_z %.3f m  load %7.1f ms  step %6.1f us  realtime x%6.0f  "
              "dyn %6.1f us  hold %s%s\n",
              model->name().c_str(), model->nq(), model->nv(), model->total_mass_kg(), model->standing_com_height_m(),
              1e3 * median(load_s), 1e6 * step, dt / step, 1e6 * median(dyn_s), hold.fell ? "FELL: " : "stands",
              hold.fell ? hold.failure.c_str() : "");
  if (sink == 42.0) std::printf(" ");  // keep the queries from being optimised away
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> robots;
  for (int i = 1; i < argc; ++i) robots.emplace_back(argv[i]);
  if (robots.empty()) robots = {"g1", "h1", "jvrc1", "humanoid25"};
  std::printf("model benchmark: medians of 5 runs; standing hold = 2 s simulated at the robot's timestep\n");
  for (const auto& r : robots) run(r);
  return 0;
}
