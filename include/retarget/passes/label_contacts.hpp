#pragma once
/// `label-contacts` pass (design.md §3.3): which foot is on the floor in each frame, from the source
/// foot landmarks (ankle, toe, heel where present): a foot is in contact when one of its landmarks
/// is near that landmark's resting height and barely moving horizontally. Hysteresis (separate on
/// and off thresholds) avoids chatter; phases shorter than a minimum are merged into their
/// neighbours. Both feet are in contact at frame 0 (paper §III); the data is corrected with a
/// warning when it disagrees.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct LabelContactsOptions {
  double height_on_m = 0.03;     ///< [m] above its resting height, a foot landmark may touch down below this
  double height_off_m = 0.05;    ///< [m] ... and lifts off above this
  double speed_on_mps = 0.25;    ///< [m/s] horizontal speed below which a low foot is in contact
  double speed_off_mps = 0.50;   ///< [m/s] horizontal speed above which it is not
  double min_phase_s = 0.10;     ///< [s] shorter stance or swing phases are merged into their neighbours
  double rest_percentile = 0.05; ///< resting height of a landmark: this percentile of its height
};

/// The labelling itself (exposed for tests and for labelling third-party references).
ContactSchedule label_contacts(const HumanMotion& human, const LabelContactsOptions& options, Diagnostics& diagnostics);

/// Labels the contacts of a robot motion from its own kinematics (for references that come without a
/// schedule, e.g. a third-party CSV): a foot is in contact when its lowest sole corner is near the
/// clip's floor level (the `rest_percentile` of that height) and its sole centre barely moves
/// horizontally, with the same hysteresis and minimum phase length as label_contacts.
/// `q` is nq x T at `fps`.
ContactSchedule label_robot_contacts(const RobotModel& model, RobotData& data, const MatX& q, double fps,
                                     const LabelContactsOptions& options, Diagnostics& diagnostics,
                                     const std::string& where);

/// Removes phases shorter than `min_frames` from one foot's labels: short swings are filled first,
/// then short stances dropped. Returns the number of phases changed.
int merge_short_phases(std::vector<std::uint8_t>& labels, int min_frames);

class LabelContactsPass final : public Pass {
 public:
  LabelContactsPass();
  std::string name() const override { return "label-contacts"; }
  std::string description() const override {
    return "label foot contacts from source foot height and speed, with hysteresis and a minimum phase length";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  LabelContactsOptions options_;
  OptionTable table_;
};

}  // namespace rt
