#pragma once
/// `retime` pass (issue 6): plays the source motion slower (time_scale > 1) or faster (< 1) before
/// IK, keeping the frame rate: every landmark track is resampled at t_source = t / time_scale
/// (positions linearly, orientations by slerp; a sample is as valid as the worse of its two
/// neighbours). A no-op at time_scale = 1, so it sits at the front of the default pipeline.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct RetimeOptions {
  double time_scale = 1.0;  ///< > 1 slows the clip down (2 = half speed), < 1 speeds it up
};

/// The resampling itself.
HumanMotion retime_motion(const HumanMotion& motion, double time_scale);

class RetimePass final : public Pass {
 public:
  RetimePass();
  std::string name() const override { return "retime"; }
  std::string description() const override { return "slow the source motion down (time_scale > 1) or speed it up, before IK"; }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  RetimeOptions options_;
  OptionTable table_;
};

}  // namespace rt
