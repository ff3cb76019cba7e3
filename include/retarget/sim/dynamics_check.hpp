#pragma once
/// The dynamics check (design.md §3.5, paper §IV–VII): simulate a reference in MuJoCo through a
/// controller and report every balance violation with its time span and magnitude.
///
/// The closed loop (dynamics_check.cpp) is a short composition: the Plant (plant.hpp) is measured,
/// a CheckController (check_controller.hpp) maps the reference and computes torques, and the
/// ViolationMonitor (violation_monitor.hpp) judges what happened. Controllers:
///  - walking (default, walking_controller.hpp): whole-clip COM/ZMP plan, DCM tracking with the
///    commanded COP clamped into the loaded support, receding-horizon re-planning, foothold
///    adjustment, force ramps at contact changes, blended trunk mapping;
///  - paper (paper_controller.hpp): LQR pendulum balance (eq. 1), trunk mapping (eq. 20–24) and
///    online dynamic mapping (eq. 25–34); both use the tracking controller (eq. 2–19).

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "retarget/balance/balance_controller.hpp"
#include "retarget/balance/com_replanner.hpp"
#include "retarget/control/tracking_controller.hpp"
#include "retarget/control/trunk_mapping.hpp"
#include "retarget/reference/reference.hpp"
#include "retarget/sim/violations.hpp"
#include "retarget/sim/walking_controller.hpp"

namespace rt {

class RobotModel;

enum class CheckControllerKind { Walking, Paper };

/// "walking", "paper".
const char* check_controller_name(CheckControllerKind kind);

struct DynamicsCheckOptions {
  CheckControllerKind controller = CheckControllerKind::Walking;
  WalkingControllerOptions walking;  ///< the walking controller's (its tracking gains are `tracking`)
  /// Robustness runs: the simulated robot's masses and inertias scaled, and the floor's sliding
  /// friction set (> 0), while the controller keeps the nominal model (plant.hpp).
  double mass_scale = 1.0;
  double floor_friction = 0;
  double control_period_s = 0.002;  ///< controller period; the simulation step is the robot's timestep (1 ms)
  /// [s] holding the first frame before the clip starts. Times in the result are clip times, so a
  /// violation or re-plan during the settle phase has a negative time (down to -settle_s): a span
  /// "-0.434-0.660 s" began 0.434 s before the clip's first frame.
  double settle_s = 0.5;
  bool trunk_mapping = true;        ///< paper §V-B (both controllers)
  /// Online COM re-planning (paper §VI; the walking controller's receding-horizon planner); false
  /// for ablations.
  bool dynamic_mapping = true;
  // The paper controller's options:
  /// Balance controller tracks the pendulum state of the reference COM motion (feed-forward,
  /// balance_controller.hpp) instead of regulating to each reference COM as if at rest (the
  /// paper's eq. 1, which lags a moving reference by about its velocity × 0.3 s).
  bool balance_feedforward = true;
  /// [s] Gaussian smoothing of the reference COM before it is differentiated for the feed-forward.
  double com_smoothing_s = 0.03;
  /// The trunk's horizontal reference (eq. 2) follows the balance controller's COM estimate:
  /// x_root,ref = x_root,ref + (ĉ − c_ref), with velocity and acceleration likewise. The COM is
  /// steered by the COP (the balance controller); a trunk PD towards the original position would
  /// pull the same body the other way whenever the COM deviates from its reference.
  bool root_follows_com = true;
  BalanceOptions balance;           ///< LQR / observer weights (control_period_s is overridden)
  TrackingOptions tracking;         ///< gains default to robot.yaml's controller section
  TrunkMappingOptions trunk;
  ComReplanOptions replan;          ///< N, period, h_max, w

  // Violation thresholds.
  /// A foot carries load above this fraction of the body weight: it spans the support polygon, and
  /// a reference swing foot still carrying it has not lifted off.
  double contact_force_fraction = 0.05;
  /// A foot is on the floor when it presses on it with more than this fraction of the body weight or
  /// its lowest sole corner is less than `on_floor_gap_m` above it. A reference stance foot that is
  /// not has not achieved its contact; one resting on the floor with little load has (the reference
  /// may shift nearly all the weight onto the other foot before a lift).
  double touch_force_fraction = 0.01;
  double on_floor_gap_m = 0.002;  ///< [m]
  /// [m] a reference foot labelled in contact whose sole centre is further than this from the
  /// reference's own floor fails the check (`stance-off-floor`, reference_consistency.hpp).
  /// Infinite: not checked (the validate job's setting when it labelled the contacts itself).
  double stance_height_tolerance_m = 0.05;
  double contact_tolerance_s = 0.15;     ///< [s] allowed lag between a reference contact change and the robot's
  /// The allowed lag is also at most this fraction of the reference phase it falls in (the foot's
  /// stance or swing interval): a 0.13 s swing with a 0.15 s tolerance could never show that the
  /// foot did not lift.
  double contact_tolerance_fraction = 0.5;
  double cop_margin_m = 0.01;            ///< [m] COP closer than this to the support edge is reported
  double slip_speed_mps = 0.10;          ///< [m/s] loaded stance sole's fastest corner faster than this slides (a spin too)
  /// [m] a loaded stance foot whose sole centre has moved further than this over the floor from
  /// where it was planted in that stance fails the check (`stance-foot-moved`): the robot slid
  /// through the reference instead of stepping where it steps. A quarter of a G1 sole's length;
  /// brief slips and spins (`foot-slip`) that leave the foot on its footstep are warnings only.
  double max_stance_foot_travel_m = 0.05;
  double joint_limit_margin_rad = 0.0087;  ///< [rad] (0.5°) closer than this to a limit counts as reached
  double fall_com_fraction = 0.5;        ///< COM below this fraction of its standing height = fall
  double fall_tilt_rad = 0.785398163397448;  ///< trunk tilt above this = fall (45°)
  double min_violation_s = 0.01;         ///< [s] shorter spans of a condition are ignored
  double record_period_s = 0.01;         ///< [s] sampling of the recorded time series
  /// Called with the clip time simulated so far and the clip's duration [s], about every 0.1 s of
  /// clip time (progress lines; the library never prints).
  std::function<void(double done_s, double total_s)> progress;
};

/// Time series recorded during the run (for report.json and the plots).
struct DynamicsTrace {
  std::vector<double> t_s;
  std::vector<Vec3> com_W;            ///< actual COM
  std::vector<Vec2> com_ref_W;        ///< reference COM given to the balance controller (after re-planning)
  std::vector<Vec2> com_ref_original_W;  ///< reference COM before re-planning
  std::vector<Vec2> cop_W;            ///< measured COP (NaN when nothing touches)
  std::vector<Vec2> cop_desired_W;    ///< balance controller output
  std::vector<Vec2> support_min_W, support_max_W;  ///< bounding box of the actual support polygon (NaN when none)
  std::vector<std::array<bool, 2>> contact_ref, contact_actual;
  std::vector<std::array<double, 2>> foot_force_n;
  /// Contact force per foot: measured (floor on robot) and commanded by the tracking controller
  /// (zero for a foot without a wrench) [N].
  std::vector<std::array<Vec3, 2>> foot_force_W, foot_force_cmd_W;
  std::vector<Vec2> cop_commanded_W;  ///< COP of the commanded contact wrenches (NaN when none)
  std::vector<std::array<double, 2>> foot_speed_mps;  ///< horizontal speed of each sole's fastest corner (slip measure)
  std::vector<std::array<double, 4>> tracking_error_rad;  ///< RMS joint error: legs, torso (waist+neck), arms, all
};

struct ReplanRecord {
  double t_s = 0;
  ReplanEvent event;
};

struct DynamicsCheckResult {
  bool passed = false;          ///< no violation that fails the check
  bool fell = false;
  double fall_time_s = -1;
  double simulated_s = 0;       ///< clip time simulated (the clip duration unless it fell)
  double clip_duration_s = 0;
  double wall_s = 0;
  double real_time_factor = 0;  ///< simulated seconds (settle included) per wall second
  std::vector<Violation> violations;
  // Tracking metrics over the clip.
  double joint_rms_error_rad = 0;
  /// Actual COM vs the reference motion's COM (horizontal, trunk-mapped, before re-planning): how far
  /// balancing moved the robot away from the reference.
  double com_rms_error_m = 0, com_max_error_m = 0;
  double cop_rms_error_m = 0;                       ///< measured vs desired COP
  int saturated_control_cycles = 0;
  int trunk_mapping_updates = 0;
  std::vector<ReplanRecord> replans;                ///< online dynamic-mapping activations
  /// Cost of the online planner (benchmarks): wall time spent in it and in the whole control loop
  /// from its first activation on, and the control cycles in that span.
  double planner_wall_s = 0, active_loop_wall_s = 0;
  long active_cycles = 0;
  /// Feasibility of the commanded contact wrenches on a rigid flat floor with the model's friction
  /// coefficient μ: control cycles (clip time) in which some foot's commanded wrench pulls
  /// (f_z < 0), would slide (|f_t| > μ f_z) or has its centre of pressure outside its sole.
  struct ForceFeasibility {
    long cycles = 0;            ///< control cycles with at least one contact wrench commanded
    long pulling = 0, sliding = 0, cop_outside = 0;
    double worst_friction_ratio = 0;  ///< max |f_t| / (μ f_z) over feet with f_z > 0
    /// Cycles in which the paper's unconstrained closed form violated the tracking controller's
    /// contact limits (TrackingOptions::contact) and the QP corrected it; its largest iteration
    /// count; and cycles where the QP stopped without a solution.
    long closed_form_infeasible = 0;
    int max_qp_iterations = 0;
    long qp_failures = 0;
  } force_feasibility;
  /// The walking controller's own statistics (used = false for the paper controller).
  struct WalkingStats {
    bool used = false;
    /// How far the whole-clip balance plan moved the reference's COM [m] (max at max_time_s), and
    /// how far its ZMP stays outside the shrunk support at worst (−1: no plan, reference as is).
    double plan_max_shift_m = 0, plan_rms_shift_m = 0, plan_max_shift_time_s = 0, plan_max_violation_m = 0;
    int replans = 0;                 ///< receding-horizon re-plans kept
    int replans_rejected = 0;        ///< re-plans solved but not kept: their COP left the support
    double replan_max_violation_m = 0;  ///< how far the kept re-plans' ZMP leaves its support at worst
    int foothold_adjustments = 0;    ///< control cycles that moved a touchdown
    double max_foothold_change_m = 0;
    double cop_clamped_fraction = 0; ///< of control cycles: the DCM law asked for a COP outside the support
    long early_touchdown_cycles = 0; ///< control cycles with a swing foot treated as landed early
    double max_dcm_error_m = 0;
    /// Standing lead-in before the clip (lead_in.hpp): its duration, the foot put down (−1: none),
    /// how high that foot was at frame 0, how far the root was lowered to reach the floor, and
    /// why none was added to a clip that starts on one foot (empty otherwise).
    double lead_in_s = 0;
    int lead_in_foot = -1;
    double lead_in_foot_height_m = 0;
    double lead_in_root_drop_m = 0;
    std::string lead_in_skipped;
  } walking;
  DynamicsTrace trace;
};

/// Runs the check. The reference must match the robot's joints and have a contact schedule (label
/// contacts first for third-party references). Never prints; InputError for an unusable reference.
DynamicsCheckResult run_dynamics_check(const RobotModel& model, const Reference& reference,
                                       const DynamicsCheckOptions& options = {});

/// Default options for a robot: tracking gains from robot.yaml's controller section.
DynamicsCheckOptions default_check_options(const RobotModel& model);

}  // namespace rt
