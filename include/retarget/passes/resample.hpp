#pragma once
/// `resample` pass: the robot motion at the source rate becomes the exported Reference at the
/// output rate (design.md §5, default 30 fps): positions and joint angles interpolated linearly,
/// the root orientation by slerp, contacts from the nearest source frame (a stance no export frame
/// samples is kept on the export frame nearest to it), re-planned COM and
/// predicted COP linearly. Joint columns follow the robot's export order.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct ResampleOptions {
  double fps = 30.0;  ///< [Hz] output rate
};

/// The resampling itself (also used by retiming and by tests).
Reference resample_motion(const RobotModel& model, const RobotMotion& motion, const ContactSchedule& contacts,
                          const Mat3X& com_W, const Eigen::Matrix2Xd& cop_W, double fps_out);

class ResamplePass final : public Pass {
 public:
  ResamplePass();
  std::string name() const override { return "resample"; }
  std::string description() const override { return "resample to the output rate (slerp for rotations) into the exported reference"; }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  ResampleOptions options_;
  OptionTable table_;
};

}  // namespace rt
