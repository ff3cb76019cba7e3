#pragma once
/// `ik` pass (design.md §3.2): per-frame landmark IK (ik/landmark_ik.hpp) over the scaled
/// landmarks, warm-started from the previous frame. Interpolated landmark samples count with
/// `interpolated_weight`, missing ones not at all. Reports per-frame landmark error and the worst
/// landmark.
///
/// Stance lock: when contacts are labelled (label-contacts runs first in the default pipeline), the
/// foot landmarks of a foot in stance are held at their median horizontal position over that stance
/// phase, at the robot's own height of that point above its flat sole, with the foot's orientation
/// target flat at the phase's mean heading, and weighted by `stance_weight`: per-frame IK already
/// keeps planted feet still and flat. (The human's foot proportions differ from the robot's: a
/// scaled toe landmark 6 cm under the ankle tilts a robot foot whose toe point is 3 cm under it by
/// 20° or more.) The lock applies to the IK's copy of the targets; the clip keeps the scaled human
/// landmarks, which the quality metrics compare with.
/// Re-seeding: a frame whose error is far above the clip's typical error is solved again from the
/// standing pose at the previous root pose, and the better solution kept; this gets the solver out of
/// the wrong branch (e.g. a knee or hip yaw folded the wrong way) that warm starts would keep.

#include "retarget/ik/landmark_ik.hpp"
#include "retarget/pipeline/pass.hpp"

namespace rt {

struct IkPassOptions {
  IkOptions ik;                        ///< solver options (iterations, tolerances, regulariser)
  int first_frame_iterations = 200;    ///< frame 0 starts from the standing pose: allow more iterations
  double interpolated_weight = 0.5;    ///< weight factor for gap-filled landmark samples
  double stance_weight = 5.0;          ///< weight factor of foot landmarks in stance (0: no stance lock)
  double reseed_error_m = 0.05;        ///< re-seed frames whose RMS error exceeds this ...
  double reseed_factor = 2.0;          ///< ... and this multiple of the running median error
};

/// Foot landmark targets held still and flat in stance (see file comment): for each labelled stance
/// phase, the horizontal positions of that foot's ankle, toe and heel targets become their phase
/// medians, their heights the robot's flat-foot heights, the ankle orientation flat at the mean heading.
void lock_stance_feet(const RobotModel& model, LandmarkTargets& targets, const ContactSchedule& contacts);

/// IK targets of one frame from the scaled landmarks and the robot's landmark map; `landmarks`
/// (optional) receives the landmark of each target.
std::vector<IkTarget> make_ik_targets(const RobotModel& model, const LandmarkIk& ik, const LandmarkTargets& targets,
                                      int frame, double interpolated_weight, std::vector<Landmark>* landmarks = nullptr,
                                      const ContactSchedule* contacts = nullptr, double stance_weight = 1.0);

/// Standing pose with the root moved above the frame-0 pelvis target, yawed like the pelvis.
VecX initial_guess(const RobotModel& model, const LandmarkTargets& targets);

class IkPass final : public Pass {
 public:
  IkPass();
  std::string name() const override { return "ik"; }
  std::string description() const override {
    return "per-frame landmark IK with joint limits as hard bounds (projected Levenberg-Marquardt)";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  IkPassOptions options_;
  OptionTable table_;
};

}  // namespace rt
