#pragma once
/// `com-plan` pass (issue 14, design.md §3.4; in the default pipeline, after refine and ground):
/// makes the exported motion dynamically feasible on flat ground by planning the whole clip's
/// horizontal COM over its known footsteps and moving the body onto that plan.
///
/// The pass works on the export grid (`fps`, the resample pass's rate, which `--fps` sets): the
/// ZMP is a second derivative of the motion, so it is planned and corrected on the frames it is
/// exported and measured on (clip_rate.hpp resamples the clip's per-frame arrays to that grid
/// first). A pass that keeps anything leaves the clip's motion, contacts and landmark targets at
/// the export rate (the resample pass then copies them); one that keeps nothing leaves the clip
/// as it came. Working at 30 fps rather than a 120 Hz source rate is also 4x fewer frames.
///
///  0. Lead: where the clip starts (ends) moving and standing, a standing lead-in (lead-out) that
///     holds that end's pose and contact labels is added (`lead`, clip_ends.hpp), so the plan can
///     start (stop) the COM at rest there rather than inside the clip's first (last) step. Where
///     that end stands on one foot, the lead stands on both: the other foot is put down flat below
///     where it is (ik/foot_down.hpp), and lifted into the clip's first pose (lowered from its last)
///     in 0.1 s at the lead's clip side (longer where the root was lowered to reach the floor), the
///     stance sole held; where the legs cannot do that within `foot_tolerance`, it stays on one.
///  1. Support: per frame, the hull of the sole rectangles of the feet labelled in contact
///     (stance_support.hpp), shrunk by `margin`; no constraint on flight frames.
///  2. Plan (zmp_plan.hpp): on a `period` grid, the COM closest to the retargeted COM (with a jerk
///     penalty) whose cart-table ZMP, plus the multibody correction Δp, stays in the support; rest
///     at both ends.
///  3. COM-following IK per frame: both soles held (stance soles where they are, swing soles on
///     their low-passed trajectory, raised where the low-pass would bring the centre or a corner
///     lower than it was, so refine's swing clearance holds), the COM on the plan (its height on
///     the low-passed height), the other landmarks as secondary targets, a pull towards the
///     low-passed pose, joint limits and velocity limits (around the previous frame) as bounds.
///     The ZMP is a second derivative:
///     at 30 fps a 0.1 mm COM wobble moves it by about 2.5 cm, so everything the IK follows is
///     low-passed (`smoothing`) and the IK converges to micrometres.
///  4. Multibody correction (two-stage preview, Kajita et al. 2003): the whole-body ZMP of the
///     motion from 3 (centroidal.hpp) minus the plan's cart-table ZMP is the next plan's Δp; 2-4
///     repeat until that ZMP is inside the (unshrunk) support on every stance frame, or
///     `iterations` times. The round with the fewest stance frames outside is kept, if it holds
///     the soles to `foot_tolerance`, keeps the landmark error median within
///     `max_landmark_growth` of the input's, keeps each stance sole's drift since its touchdown
///     within max(`foot_tolerance`, the input's) and beats the retargeted motion. A round that
///     does not hold the soles is repaired locally (`repairs`): the plan pinned to the retargeted
///     COM around the frames that gave, and frames that still give left as they came.
///  5. Whole-body stage: the angular-momentum part that the rounds only predict (each round's IK
///     changes it) is removed by refine's smooth joint-space correction with one-sided multibody
///     ZMP rows (src/refine/smooth_correction.hpp): the smallest smooth change whose ZMP, by the
///     frames' own finite differences, lies inside the shrunk support (and whose COM does not
///     fall faster than 0.7 g where there is a support), stance soles held, swing
///     soles on their paths, floor, limits and speed limits kept (rows that are penalties: joints
///     are then clamped to their limits, frames whose stance soles gave are projected back onto
///     them, swing soles that came below the 1.5 cm clearance, or more than `foot_tolerance`
///     below where they were near lift-off and touchdown, are lifted back, and steps are cut to
///     the speed limits). The stage has no ZMP rows at frames a repair left as they came. Where it
///     still breaks a sole (moved, turned, tilted, drifting, a swing sole too low, or the body
///     lower below the floor than before), those frames take the rounds' motion back, blended in
///     over 0.1 s either side and projected onto the held soles (at most six times,
///     `whole_body_give_back`). Kept if the ZMP improves, the stance soles hold to `foot_tolerance`
///     (and their drift as in 4), no swing sole stays too low and the landmarks hold to
///     `max_landmark_growth`. Where it cannot be kept on the rounds' result, the stage starts from
///     the retargeted motion itself, and that is kept if it ends better than the rounds' result.
///  If neither 4 nor 5 is kept, the clip is left as it came (with a warning).
///
/// The planned COM (3 x T: plan x, y; the low-passed height) and the plan's ZMP go to the
/// reference (meta.json and NPZ `com_pos_w`, `zmp_w`) as the balance reference.

#include "retarget/balance/zmp_plan.hpp"
#include "retarget/pipeline/pass.hpp"

namespace rt {

struct ComPlanPassOptions {
  /// Grid, tracking and jerk weights, rest at the ends. The grid is 20 ms (the plan's own default
  /// is 10 ms), and at most the export period: finer than the frames it is followed on, at half the
  /// QP's size (the CMU walk's plan took a fifth of the pass at 10 ms; the ZMP fractions of the
  /// shared gaits moved by at most 3 points either way).
  ZmpPlanOptions plan = [] {
    ZmpPlanOptions o;
    o.period_s = 0.02;
    return o;
  }();
  /// [s] standing lead-in (lead-out) added where the clip starts (ends) moving with a foot down, so
  /// the plan can start (stop) the COM at rest without bending the first (last) step (clip_ends.hpp;
  /// the summary and meta.json `lead_in_s` / `lead_out_s` say so). It stands on both feet (step 0).
  /// 0: none, the rested end is the clip's own.
  double lead_s = 1.0;
  double lead_speed_mps = 0.1;         ///< [m/s] horizontal COM speed (over 0.1 s) above which an end is moving
  double margin_m = 0.015;             ///< [m] the planned ZMP keeps this far inside each support polygon
  /// Plan (and correct, in the whole-body stage) the ZMP inside each sole's ankle reach
  /// (model/ankle_reach.hpp: where the ankle's effort limit holds the COP under the robot's weight),
  /// the support the dynamics check's controller has, rather than the whole sole: on G1 the toe's
  /// last 4 cm is beyond its 35 N m ankle pitch. The ZMP metric still counts the whole soles.
  bool ankle_reach = true;
  double max_offset_m = 0.2;           ///< [m] the multibody correction Δp is clipped to this length
  int iterations = 3;                  ///< plan + COM-following rounds (multibody correction)
  /// Local repair of a round that does not hold the soles. Where following a round's plan moves a
  /// held sole beyond `foot_tolerance` or takes a stance sole's drift beyond the allowed (a COM the
  /// legs cannot carry there: a joint limit, the reach, a glitch of the input), the plan's samples
  /// within `pin_window` of those frames are pinned to the retargeted COM (on a copy: the next
  /// round's multibody correction still comes from the unrepaired motion) and the plan is solved
  /// and followed again, with the floor held by the IK. Then, at most `repairs` times, the frames
  /// that still give keep their input pose (with two frames either side; a kept frame whose stance
  /// still drifts keeps that whole stance), the frames within 0.1 s of them follow a pose and COM
  /// blended towards the input's and stay within the speed limits of it, and the same plan is
  /// followed again. The repaired round is a candidate beside the others. Without it, one such
  /// passage dropped every round of a long clip: the LAFAN1 dance kept nothing on any robot (G1:
  /// 150 of its 3,945 frames gave). 0: no repair (such a round is dropped).
  int repairs = 2;
  double pin_window_s = 0.3;           ///< [s] see `repairs`
  double smoothing_s = 0.03;           ///< [s] σ of the Gaussian low-pass of the pose and the COM height
  /// [s] σ of the low-pass of the swing soles' trajectories (0: as they are). Swing soles carry the
  /// heaviest moving links; at 0.03 s their angular momentum rate doubled the ZMP's angular part on
  /// the shared gaits (CMU, GAMES-105, OpenSim), 0.06 s keeps it at the low-passed motion's.
  double swing_smoothing_s = 0.06;
  double com_weight = 1e6;             ///< COM-following IK: weight of the COM target [1/m²]
  double foot_weight = 1e8;            ///< ... weight holding each sole's pose (>> com_weight: feet win)
  double landmark_factor = 1.0;        ///< ... factor on the robot.yaml weights of the non-foot landmarks
  /// ... pull towards the low-passed configuration: 1 (rather than 1e-2) keeps the body's null-space
  /// motion from adding angular momentum (ZMP within 1 cm on 62 % instead of 45 % of OpenSim's gait)
  double posture_regularization = 1.0;
  int ik_iterations = 20;
  double velocity_margin = 0.02;       ///< fraction of each URDF velocity limit the frame-to-frame bounds keep free
  double foot_tolerance_m = 0.001;     ///< [m] a round whose IK moves a held sole further is dropped (issue 13's drift bar)
  /// [m] a round or the whole-body stage that grows the landmark error median (over the clip's own
  /// frames, the summary's metric) by more is dropped: a plan followed only by distorting the
  /// motion is reported (a warning), not exported (H1, whose legs lack an ankle roll, once moved
  /// the Qualisys gait's median from 7.9 to 22.8 cm for 1 point of ZMP fraction).
  double max_landmark_growth_m = 0.02;
  double follow_tolerance_m = 0.001;   ///< [m] frames whose COM misses the plan by more are reported
  /// Whole-body stage (5): Gauss–Newton iterations of the smooth joint-space correction with the
  /// multibody ZMP rows, on the export grid (0: off).
  int whole_body_iterations = 20;
  /// Where plain Gauss–Newton stops with a ZMP row more than 1 cm beyond the support (past the
  /// margin), the stage is solved again with at most this many more steps while a ZMP, stance or
  /// limit row is still missed, a step that no backtracking makes cheaper being retried damped
  /// (Levenberg–Marquardt, refine's `hold_iterations` mechanism, smooth_correction.hpp) instead of
  /// ending the stage. Measured with the compact-stencil ZMP (2026-12-07; plain Gauss–Newton, 5, 20
  /// further steps): JVRC-1's PyMO walk 93, 100, 100 % of the stance frames within 1 cm,
  /// humanoid25's 86, 90, 95 %, its CMU walk 94, 100, 100 %; the stage stops by itself on the
  /// LAFAN1 dance (15 steps, G1). Where every row is within 1 cm already the retries only polish
  /// (G1's CMU walk: 200 ms more, no frame gained), so they are not run there. 0: plain
  /// Gauss–Newton only. The stage is also
  /// dropped where it turns a stance sole by more than 0.5° or tilts one beyond 0.5° (issue 13's
  /// bars; more than it was, where it already was): on H1's mocap36 gait the retries reached 65 %
  /// with a sole tilted 0.61°.
  int whole_body_extra_iterations = 20;
  /// Where the whole-body stage breaks a sole (moved, turned, tilted or drifting, a swing sole too
  /// low, the body lower below the floor than before), those frames take the stage's start back,
  /// blended in over 0.1 s either side and projected onto the held soles, at most six times;
  /// false: such a stage is dropped whole, as one frame dropped the stage of a whole dance.
  bool whole_body_give_back = true;
  double whole_body_zmp_weight = 1e4;    ///< [1/m²] weight of a ZMP half-plane row
  double whole_body_smoothing_hz = 1.0;  ///< [Hz] cutoff of the correction's smoothness term
  /// [Hz] the export rate (the resample pass's; `--fps` sets both): the pass works on that grid,
  /// where the exported motion's ZMP is measured by finite differences.
  double export_fps = 30.0;
};

class ComPlanPass final : public Pass {
 public:
  ComPlanPass();
  std::string name() const override { return "com-plan"; }
  std::string description() const override {
    return "plan the whole clip's COM so its multibody ZMP stays in the support polygon; COM-following IK with feet fixed";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  ComPlanPassOptions options_;
  OptionTable table_;
};

}  // namespace rt
