#pragma once
/// `flat-contact` pass (paper §V-A, design.md §3.3): at frame 0 the feet in contact are projected
/// flat onto the floor (sole plane horizontal, keeping the foot's heading; sole centre at z = 0), IK
/// finds the joint angles that achieve this starting from the original angles (root held, except its
/// height), and the joint-angle differences are added to every frame.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct FlatContactOptions {
  double sole_weight = 100.0;        ///< weight of the sole position and orientation targets
  double regularization = 1e-3;      ///< pull towards the original frame-0 angles (non-foot joints stay put)
  int max_iterations = 100;
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
    return "frame-0 feet flat on the floor by IK; the joint-angle differences are added to every frame";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  FlatContactOptions options_;
  OptionTable table_;
};

}  // namespace rt
