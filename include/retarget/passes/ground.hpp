#pragma once
/// `ground` pass (design.md §3.2): vertical placement of the whole robot so that the lowest sole
/// corner of the feet in stance touches the floor, and no sole corner is ever below it. The per-frame
/// offset is taken from stance frames, interpolated across frames without stance, smoothed, and then
/// raised wherever a sole would still penetrate.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct GroundOptions {
  double smoothing_s = 0.1;  ///< [s] width of the moving average applied to the height offset
};

class GroundPass final : public Pass {
 public:
  GroundPass();
  std::string name() const override { return "ground"; }
  std::string description() const override {
    return "put the lowest stance sole on the floor and keep every sole above it";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  GroundOptions options_;
  OptionTable table_;
};

}  // namespace rt
