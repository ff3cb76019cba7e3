#pragma once
/// `scale` pass (design.md §3.2): human landmarks -> robot proportions.
///
/// Landmarks form a tree rooted at the pelvis (pelvis -> hip -> knee -> ankle -> toe/heel;
/// pelvis -> spine -> chest -> neck -> head; chest -> shoulder -> elbow -> wrist -> hand). Each
/// segment's ratio is robot length / human length, the human length being the median over the clip
/// (a robust "rest" length) and the robot length the distance between the mapped link points in the
/// robot's zero configuration. Every frame is rebuilt root-relatively: a child is placed at its
/// parent's scaled position plus the ratio times the human segment vector. The pelvis trajectory
/// (horizontal and vertical) is scaled by the leg-length ratio, so strides and root height match
/// the robot's legs.

#include <optional>

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct ScaleOptions {
  double min_ratio = 0.3;  ///< segment ratios are clamped to [min_ratio, max_ratio] (with a warning)
  double max_ratio = 3.0;
  double min_segment_m = 0.02;  ///< human segments shorter than this keep ratio = leg ratio
};

/// Parent of each landmark in the scaling tree (the pelvis has none), with fallbacks when a parent
/// is absent from the source: returns the nearest present ancestor, or nullopt for the root.
std::optional<Landmark> scale_parent(const HumanMotion& human, Landmark l);

class ScalePass final : public Pass {
 public:
  ScalePass();
  std::string name() const override { return "scale"; }
  std::string description() const override {
    return "scale human landmarks to the robot: per-segment root-relative ratios, root by leg length";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  ScaleOptions options_;
  OptionTable table_;
};

}  // namespace rt
