#pragma once
/// `refine` pass (design.md §3.2): turns the per-frame IK result into a trajectory a robot can be
/// given — smooth, within the joint position and velocity limits, feet fixed on the floor in every
/// labelled stance, swing feet clear of the floor, no part of the robot below the floor — at the
/// source rate, on every frame (not only at knots).
///
/// 1. Ground. The robot is moved vertically by the ground pass's own per-frame offset, so that the
///    stance feet of the IK result are near the floor before anything else.
/// 2. Anchors. Every labelled stance phase gets one sole pose: flat on the floor, at the median
///    position and mean heading of the IK result's sole over the phase (refine/foot_plan.hpp says
///    how pivots and swings follow from that).
/// 3. Smooth. Each generalised coordinate (root position, the root quaternion with sign
///    continuity, each joint) is smoothed on its own by a zero-phase second-order low-pass with the
///    joint position limits and the joint speed limits (URDF, or `max_joint_speed` when lower, less
///    `velocity_margin`) as constraints (refine/signal_smoother.hpp): O(T), no windows. The loss is
///    robust (Huber): a few frames where per-frame IK took the wrong branch are removed, not smeared.
/// 4. Plan the feet (refine/foot_plan.hpp, from the first smoothing): stance soles at their
///    anchors; swing soles re-timed between the anchors, flat and vertical at lift-off and
///    touchdown, with `swing_clearance` under their lowest corner.
///    Opt-in (`root_rise_accel`, `root_fall_accel`): the smoothed root height is put under the
///    height from which both legs reach their stance soles (at most `root_max_drop_m` below its
///    smoothed height), with its vertical acceleration limited in stance
///    (refine/signal_smoother.hpp, smooth_under_ceiling), and the projection and the correction
///    hold it 100 times stiffer: the IK's root dips at each long double support (1-2 g up at the
///    lift-off) are spread out and the knees bend instead. Opt-in (`max_leg_extension` < 1, also
///    without the acceleration limits): the same bound with each leg's reach cut to that fraction
///    of its straight length, so that the stance knees stay bent: on straight legs (G1's walks hold
///    0.98-1.01) a sole target the leg cannot quite reach moves the root, which lurches at every step.
///    Turns beyond the legs (`hold_turns`): where a performer turns on a planted foot further than
///    the robot's hip yaw allows (a pirouette), the smoothed root is turned back about the stance
///    anchor by the excess (the sole's heading relative to the root, unwrapped over the stance,
///    beyond the hip yaw joint's limits widened by `turn_slack`), blended over ±0.1 s; the body's
///    heading catches up after the stance. The projection (5) turns the root through the slack
///    itself, as it did every turn before; beyond it, it reached for the anchor by contorting the
///    leg (G1 on the LAFAN1 dance: root 0.16 m high, knee at its limit, for a second). Where a turn
///    is held back, steps 3-6 run both with and without it and the result that misses fewer frames
///    (stance hold and joint speed) is kept.
/// 5. Project each frame on its own: the least change (in generalised coordinates, the legs 30-100
///    times cheaper than the root and the rest) that puts its soles on their targets and every
///    collision point of the robot (collision_hull.hpp) above the floor — the landmark IK with
///    those targets and a floor term, joint limits as bounds. This meets every row but is jittery.
///    Each frame starts from the previous one's correction; at a touchdown or lift-off it is also
///    solved afresh, which is kept where it meets the rows much better unless it moves a joint more
///    than 6 times its speed limit from the previous frame (another branch of the leg's solutions).
/// 6. Correct smoothly (refine/smooth_correction.hpp): from the projection, Gauss–Newton over the
///    whole clip for the smallest smooth change of the smoothed motion that meets the same rows,
///    the joint position limits and the speed limits; the change is weighed by the landmark cost's
///    Gauss–Newton matrix of each frame (`landmark_metric`), so it goes where the body's landmarks
///    move least.
/// 7. Repeat 3, 5, 6 from the result (at most `rounds` times) while a joint is faster than its
///    limit; what the limit penalties leave (micro-radians) is clamped.
///
/// Replaces the windowed Ipopt NLP (still available as `refine-ipopt` for ablation), which held the
/// stance only at collocation knots and took 98 % of a 30 fps conversion.

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct RefineOptions {
  double smoothing_hz = 6.0;         ///< [Hz] cutoff (half amplitude) of the joint-space smoother; 0 disables smoothing
  double root_rise_accel = 0;        ///< [m/s²] largest upward acceleration of the root height in stance (0: none)
  double root_fall_accel = 0;        ///< [m/s²] largest downward acceleration of the root height in stance (0: none)
  double root_max_drop_m = 0.04;     ///< [m] with those limits: the deepest the legs' reach may put the root below its smoothed height
  /// Largest hip-ankle distance of a stance leg as a fraction of its straight length (< 1 turns the
  /// root bound of step 4 on, with root_max_drop as its depth; README "Bent knees").
  double max_leg_extension = 1.0;
  double robust_threshold = 3.0;     ///< [σ] samples this far from the smoothed curve are weighted down (Huber); 0: plain
  double velocity_margin = 0.02;     ///< fraction of each joint speed limit kept free
  double max_joint_speed = 0;        ///< [rad/s] optional cap on every joint's speed below its URDF limit (0: none)
  double limit_margin = 1e-4;        ///< [rad, m] distance kept from the joint position limits
  double swing_clearance_m = 0.015;  ///< [m] swing soles stay this high beyond swing_guard of lift-off and touchdown
  double swing_guard_s = 0.1;        ///< [s]
  /// [s] Opt-in: the swing sole's tilt (the performer's toe-off and heel strike) fades in after
  /// lift-off and out before touchdown over this time instead of swing_guard (at most half the
  /// swing); 0: over swing_guard. 0.25 lowers the torque demand and jitter of most references
  /// (README "Swing tilt"); it is not the default because it moves com-plan's results both ways.
  double swing_tilt_ramp_s = 0;
  double stance_weight = 1e6;        ///< weight of a sole's position target [1/m²] (orientation: × (0.1 m)²)
  double swing_weight = 1e3;         ///< weight of a swing sole's target [1/m²]
  double floor_weight = 1e6;         ///< weight of a collision point below its floor height [1/m²]
  /// Step 4: hold back the root's turn where a stance sole's heading relative to the root leaves the
  /// range of the leg's hip yaw joint by more than `turn_slack` [rad] (kept where it misses fewer
  /// frames). Within the slack the projection turns the root itself: it holds the shared walks'
  /// stances there, and holding the turn back from the limit instead tilted humanoid25's PyMO
  /// stances 0.57 deg (0.29 without).
  bool hold_turns = true;
  double turn_slack = 0.5;
  int rounds = 3;                    ///< smooth + project rounds at most
  /// Opt-in: at most this many further Gauss–Newton steps of the smooth correction (6) while a
  /// stance sole is more than 0.5 mm or 0.23 deg off its anchor or a limit is missed by more than
  /// 1 mrad, a step that fails being retried damped (Levenberg–Marquardt) rather than ending the
  /// solve. On H1, whose five-joint legs run into their hip-yaw and ankle limits, 8 (with
  /// stance_weight 2e6) holds most walks' stances better; it costs time, and on the dances and
  /// jumps it holds them worse (README, "Stances on H1").
  int hold_iterations = 0;
  int max_iterations = 30;           ///< projection iterations per frame
  bool landmark_metric = true;       ///< weigh the foot correction by the landmark cost's Gauss–Newton matrix
};

class RefinePass final : public Pass {
 public:
  RefinePass();
  std::string name() const override { return "refine"; }
  std::string description() const override {
    return "smooth within position/speed limits, then hold stance soles fixed and flat on every frame, swing soles clear, "
           "nothing below the floor";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  RefineOptions options_;
  OptionTable table_;
};

}  // namespace rt
