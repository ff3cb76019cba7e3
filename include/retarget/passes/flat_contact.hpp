#pragma once
/// `flat-contact` pass (paper §V-A, design.md §3.3): at the first frame where both feet are labelled
/// in contact (frame 0 in the paper, which assumes both feet down there) the feet are projected flat
/// onto the floor (sole plane horizontal, keeping the foot's heading; sole centre at z = 0), IK finds
/// the joint angles that achieve this starting from the original angles (root held, except its
/// height), and the joint-angle differences are added to every frame.
///
/// Only where the paper's assumption holds: with no frame that has both feet down the pass does
/// nothing (with a warning); no joint gets an offset larger than `max_offset`; and the offsets are
/// halved (down to a quarter, else dropped, with a warning) while they make the clip's landmark error
/// worse by more than `max_error_growth`: a constant offset that helps one frame must not distort the
/// whole clip. The refine pass holds every stance sole flat on every frame in any case.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct FlatContactOptions {
  double sole_weight = 100.0;        ///< weight of the sole position and orientation targets
  double regularization = 1e-3;      ///< pull towards the original frame-0 angles (non-foot joints stay put)
  int max_iterations = 100;
  double max_offset_rad = 0.3;       ///< [rad] largest offset added to any joint
  double max_error_growth = 0.10;    ///< largest allowed relative growth of the mean landmark error
};


/// Sole tilt [rad] (angle between the sole normal and the vertical) and sole-centre height [m] of a
/// foot at configuration q.
std::pair<double, double> sole_tilt_and_height(const RobotModel& model, RobotData& data, const VecX& q, int foot,
                                               const Mat3& R_L_sole);

class FlatContactPass final : public Pass {
 public:
  FlatContactPass();
  std::string name() const override { return "flat-contact"; }
  std::string description() const override {
    return "feet flat on the floor by IK at the first frame with both feet down; the bounded joint-angle differences are added to every frame";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  FlatContactOptions options_;
  OptionTable table_;
};

}  // namespace rt
