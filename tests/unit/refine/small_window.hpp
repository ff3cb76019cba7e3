#pragma once
/// A small refine window for the NLP and solver tests: humanoid25, 14 frames of the synthetic clip
/// at 60 Hz with stride 2 (10 control points x 31 coordinates), stance, floor, still and velocity
/// rows, a free and a fixed stance anchor.

#include <algorithm>
#include <random>

#include "refine_test_util.hpp"
#include "retarget/passes/ik_pass.hpp"
#include "src/refine/trajectory_chart.hpp"
#include "src/refine/window_nlp.hpp"

namespace rt::refine::test {

using namespace rt::test;

struct SmallWindow {
  const RobotModel& model = rt::test::robot("humanoid25");
  NlpRobot robot{model, 1e-4};
  RobotData data{model};
  WindowSpec spec;
  NlpWeights weights;
};

// 14 frames of the synthetic clip; left foot in stance on frames 0..8 (free anchor), right foot
// swinging (floor rows) until frame 8 and in stance from frame 10 (anchor fixed by "an earlier
// window"), still rows at the phase boundaries when `still`.
inline void build(SmallWindow& w, int num_pinned, bool still, const std::vector<std::uint8_t>& free_coordinates = {}) {
  const int T = 14, stride = 2;
  const double fps = 60;
  Clip clip = synthetic_clip(w.model, nullptr, T, fps);
  MatX X(w.model.nv(), T);
  for (int f = 0; f < T; ++f) X.col(f) = chart_from_q(clip.motion.q.col(f), 0.0);
  const MatX C = spline_fit(X, stride);
  w.spec.first_control = 0;
  w.spec.num_pinned = num_pinned;
  w.spec.controls = C;
  w.spec.segment_s = stride / fps;
  w.spec.free_coordinates = free_coordinates;
  const LandmarkIk ik(w.model);
  update_kinematics(w.model, w.data, clip.motion.q.col(0));
  StanceAnchor left{0, false, Vec2(0.01, 0.1)}, right{1, true, Vec2(0.02, -0.1)};
  const bool contacts = free_coordinates.empty() || free_coordinates[0];
  if (contacts) w.spec.anchors = {left, right};
  for (int f : {0, 2, 4, 6, 8, 10, 12, 13}) {
    CollocationPoint p;
    p.frame = f;
    p.support = spline_support(static_cast<double>(f) / stride, static_cast<int>(C.cols()));
    if (p.support.index[static_cast<std::size_t>(p.support.count - 1)] < num_pinned) continue;
    p.targets = make_ik_targets(w.model, ik, clip.targets, f, 0.5);
    p.x_ik = X.col(f);
    if (contacts) {
      p.stance = {{f <= 8 ? 0 : -1, f >= 10 ? 1 : -1}};
      p.floor = {{false, f <= 8}};
      p.still = {{still && f == 8, still && f == 10}};
    }
    w.spec.points.push_back(p);
  }
  w.weights.velocity_activation = 0;  // every velocity row
}

inline VecX perturbed_point(const WindowNlp& nlp) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  VecX x = nlp.initial_point();
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i] + u(rng), nlp.x_lower()[i], nlp.x_upper()[i]);
  return x;
}

}  // namespace rt::refine::test
