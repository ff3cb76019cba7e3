#pragma once
/// The controller interface of the dynamics check's closed loop (issue 15): each control cycle the
/// loop (dynamics_check.cpp) measures the plant, hands the measurement to a CheckController, which
/// maps the reference and returns joint torques together with what it aimed at, and hands both to
/// the ViolationMonitor. The paper's controller (paper_controller.hpp) and the walking controller
/// (walking_controller.hpp) sit behind it; a third needs only this interface.

#include <array>

#include "retarget/control/tracking_controller.hpp"
#include "retarget/sim/plant.hpp"
#include "retarget/sim/reference_signal.hpp"

namespace rt {

struct DynamicsCheckResult;

/// Per foot, from the plant's contacts this cycle.
struct FootStates {
  std::array<bool, 2> loaded{};      ///< normal force above the load threshold: spans the support
  std::array<bool, 2> on_floor{};    ///< pressing on the floor or resting on it (lowest corner close)
  std::array<double, 2> sole_z_m{};  ///< lowest sole corner height
};

/// What the loop measured at the start of a control cycle.
struct ControlInput {
  double t_sim_s = 0;   ///< simulation time (settle included)
  double t_clip_s = 0;  ///< clip time: t_sim − settle (negative while settling)
  /// Time on the controller's reference signal: t_sim − settle. It equals the clip time unless a
  /// standing lead-in (lead_in.hpp) was prepended to the reference, which then runs before t = 0.
  double t_signal_s = 0;
  double t_ref_s = 0;   ///< t_signal clamped to the signal: the reference instant
  bool settling = false;  ///< before the clip's first frame (settle phase and lead-in): not monitored
  const VecX* q = nullptr;
  const VecX* v = nullptr;
  const ContactState* contacts = nullptr;
  const FootStates* feet = nullptr;
  /// The controller's RobotData, already current for (q, v) (positions, velocities, dynamics).
  RobotData* data = nullptr;
  Vec3 com_W = Vec3::Zero();  ///< measured COM
};

/// What the controller commands and what it aimed at (for the monitor and the traces).
struct ControlOutput {
  ReferenceSample reference;        ///< the reference at this instant, after the controller's mapping
  TrackingReference tracking;       ///< the desired state given to the tracking controller
  TrackingCommand command;          ///< torques and contact wrenches
  Vec2 com_ref_W = Vec2::Zero();    ///< COM the balance controller steers to (after re-planning)
  /// The reference motion's own COM (trunk-mapped, before any balance planning): the tracking error
  /// of the COM is measured against it.
  Vec2 com_ref_original_W = Vec2::Zero();
};

class CheckController {
 public:
  virtual ~CheckController() = default;
  /// One control cycle. `out` is reused across cycles (its storage is kept).
  virtual void control(const ControlInput& in, ControlOutput& out) = 0;
  /// Whether the controller's online planner has acted (the loop times the cycles from then on).
  virtual bool planner_active() const { return false; }
  /// Adds the controller's own statistics (re-plans, mapping updates, planner time) to `result`.
  virtual void finish(DynamicsCheckResult& result) const = 0;
};

}  // namespace rt
