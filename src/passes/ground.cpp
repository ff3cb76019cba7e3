#include "retarget/passes/ground.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

GroundPass::GroundPass() {
  table_.add("smoothing", options_.smoothing_s, "[s] moving-average width of the height offset", {0, 10, "s"});
}

void GroundPass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  RobotMotion& motion = clip.motion;
  const int T = motion.num_frames();
  if (T == 0) throw InputError("--passes", "ground needs the robot motion of the ik pass: put ik before ground");
  std::vector<double> stance_z(static_cast<std::size_t>(T), NAN), all_z(static_cast<std::size_t>(T));
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, motion.q.col(f));
    double lowest_all = INFINITY, lowest_stance = INFINITY;
    for (int foot = 0; foot < 2; ++foot) {
      const double z = lowest_sole_corner_z(model, data, foot);
      lowest_all = std::min(lowest_all, z);
      const bool stance = clip.contacts.empty() || clip.contacts.in_contact[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)];
      if (stance) lowest_stance = std::min(lowest_stance, z);
    }
    all_z[static_cast<std::size_t>(f)] = lowest_all;
    if (std::isfinite(lowest_stance)) stance_z[static_cast<std::size_t>(f)] = lowest_stance;
  }
  // Required offset in stance; linear across frames without stance, held before the first and after
  // the last stance frame (zero when there is no stance at all).
  std::vector<double> offset(static_cast<std::size_t>(T), 0.0);
  std::vector<int> stance;
  for (int f = 0; f < T; ++f)
    if (!std::isnan(stance_z[static_cast<std::size_t>(f)])) stance.push_back(f);
  for (int f = 0, k = 0; f < T && !stance.empty(); ++f) {
    while (k + 1 < static_cast<int>(stance.size()) && stance[static_cast<std::size_t>(k + 1)] <= f) ++k;
    const int a = stance[static_cast<std::size_t>(k)];
    const double va = -stance_z[static_cast<std::size_t>(a)];
    if (f <= a || k + 1 == static_cast<int>(stance.size())) {
      offset[static_cast<std::size_t>(f)] = va;
      continue;
    }
    const int b = stance[static_cast<std::size_t>(k + 1)];
    const double w = static_cast<double>(f - a) / (b - a);
    offset[static_cast<std::size_t>(f)] = (1 - w) * va - w * stance_z[static_cast<std::size_t>(b)];
  }
  // Smooth, then never below the floor.
  const int half = std::max(0, static_cast<int>(std::lround(0.5 * options_.smoothing_s * motion.fps)));
  std::vector<double> smooth(static_cast<std::size_t>(T));
  for (int f = 0; f < T; ++f) {
    double sum = 0;
    int n = 0;
    for (int g = std::max(0, f - half); g <= std::min(T - 1, f + half); ++g, ++n) sum += offset[static_cast<std::size_t>(g)];
    smooth[static_cast<std::size_t>(f)] = sum / n;
  }
  double max_shift = 0, max_raise = 0;
  for (int f = 0; f < T; ++f) {
    double d = smooth[static_cast<std::size_t>(f)];
    const double raise = std::max(0.0, -(all_z[static_cast<std::size_t>(f)] + d));
    d += raise;
    max_raise = std::max(max_raise, raise);
    max_shift = std::max(max_shift, std::abs(d));
    motion.q(2, f) += d;
  }
  ctx.statistics.set("max-height-shift", max_shift, "m");
  ctx.statistics.set("max-penetration-fix", max_raise, "m", "raise beyond the stance offset to clear the floor");
}

}  // namespace rt
