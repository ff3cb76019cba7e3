#pragma once
/// `label-contacts` pass (design.md §3.3): which foot is on the floor in each frame, from the source
/// foot landmarks (ankle, toe, heel where present).
///
/// 1. Heel strike and toe off: a foot is in contact when its lowest landmark (relative to that
///    landmark's resting height on the levelled floor, floor_plane.hpp) is low and barely moving
///    horizontally. Thresholds are relative to the subject's leg length and speeds are taken on the
///    source timeline (HumanMotion::time_scale), so the labels are the same for every `--time-scale`.
///    Hysteresis (separate on and off thresholds) avoids chatter; phases shorter than a minimum are
///    merged into their neighbours.
/// 2. A stance foot on every frame: a run of frames with no foot in contact is a flight phase only
///    when both feet are clearly airborne (above `airborne_height` for most of it); otherwise the
///    feet were on the floor but moving (a slide, a shuffle, a heel strike faster than the speed
///    threshold): each frame of the run goes to the foot closer to the thresholds (lower and
///    slower), with a cost per change of foot so that near-equal feet do not alternate, and a foot
///    handed the weight in the middle of the run keeps it for at least `min_phase_s`.
/// 3. Weight transfers: where one foot lifts off while the other is in contact, both are in contact
///    together for at least `min_double_support` (human walking has ~20 % double support): a
///    shorter overlap is widened symmetrically, never into a neighbouring phase of the same foot.
/// No foot is forced down at frame 0: the flat-contact pass uses the first frame with both feet down.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct LabelContactsOptions {
  double height_on = 0.035;          ///< [leg lengths] above its resting height, a foot landmark may touch down below this
  double height_off = 0.06;          ///< [leg lengths] ... and lifts off above this
  double speed_on = 0.30;            ///< [leg lengths / s, source time] horizontal speed below which a low foot is in contact
  double speed_off = 0.60;           ///< [leg lengths / s, source time] horizontal speed above which it is not
  double min_phase_s = 0.10;         ///< [s, source time] shorter stance or swing phases are merged into their neighbours
  double min_double_support_s = 0.08;  ///< [s, source time] overlap of the two feet's contact at a weight transfer
  double airborne_height = 0.06;     ///< [leg lengths] both feet above this: airborne (a flight phase)
  double rest_percentile = 0.05;     ///< resting height of a landmark: this percentile of its height
};

/// What labelling found (the pass's statistics).
struct ContactLabelling {
  ContactSchedule schedule;
  int flight_phases = 0, flight_frames = 0;  ///< runs of frames with both feet airborne
  int filled_frames = 0;        ///< frames with no foot in contact that were not a flight: given to a foot
  int widened_transfers = 0;    ///< weight transfers whose double support was widened
  double size_m = 0;            ///< the leg length the thresholds were scaled by
};

/// Per-frame height above rest [m] and horizontal speed [m/s, source time] of one foot, the inputs
/// of the labelling; height is +inf where no landmark of the foot is valid.
struct FootTrack {
  std::vector<double> height_m, speed_mps;
};

/// Labels both feet from their tracks (steps 1-3 of the file comment). `frames_per_source_s` is the
/// clip's frames per second of the source timeline; `size_m` the leg length the relative thresholds
/// are scaled by.
ContactLabelling label_feet(const std::array<FootTrack, 2>& feet, double frames_per_source_s, double size_m,
                            const LabelContactsOptions& options);

/// The labelling of a human motion (exposed for tests).
ContactLabelling label_contacts(const HumanMotion& human, const LabelContactsOptions& options);

/// Labels the contacts of a robot motion from its own kinematics (for references that come without a
/// schedule, e.g. a third-party CSV): a foot's height is its lowest sole corner above the clip's
/// floor level (the `rest_percentile` of that height), its speed the sole centre's; the thresholds
/// are scaled by the robot's standing root height. `q` is nq x T at `fps`.
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
    return "gait contact labels from source foot height and speed (size-relative, source timeline), a stance foot on "
           "every frame but real flights, a minimum double support at weight transfers";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  LabelContactsOptions options_;
  OptionTable table_;
};

}  // namespace rt
