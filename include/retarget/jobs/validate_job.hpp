#pragma once
/// The `validate` job (design.md §1): read a reference (ours or another tool's), check it against
/// the robot, label its contacts from its own kinematics when it has no schedule, and run the
/// dynamics check. Never prints.

#include <string>

#include "retarget/core/diagnostics.hpp"
#include "retarget/passes/label_contacts.hpp"
#include "retarget/reference/reference.hpp"
#include "retarget/sim/dynamics_check.hpp"

namespace rt {

struct ValidateRequest {
  std::string reference_path;
  double fps = 0;                    ///< [Hz] required for a plain CSV without meta.json
  /// The joint order of an NPZ without joint_names (--joint-order: an MJCF or a YAML list,
  /// npz_layout.hpp read_joint_order); "" = such an NPZ is refused.
  std::string joint_order_path;
  DynamicsCheckOptions check;        ///< start from default_check_options(model)
  LabelContactsOptions contacts;     ///< for references without a contact schedule
};

struct ValidateResult {
  Reference reference;
  bool contacts_labelled = false;    ///< the schedule was derived from the reference's kinematics
  DynamicsCheckResult check;
  Diagnostics diagnostics;
};

/// Reads the reference. InputError for unreadable or inconsistent files (one line, with location).
/// `joint_order_path` as ValidateRequest::joint_order_path.
Reference read_reference_for(const RobotModel& model, const std::string& path, double fps,
                             const std::string& joint_order_path = "");

ValidateResult run_validate(const ValidateRequest& request, const RobotModel& model);

/// Feasibility speed (issue 6): the fastest playback of the reference at which the check passes,
/// over the time scale S (the reference played S times slower; speed = 1/S). Passing is not
/// monotone in S: a slower walk asks less of the controller but more of the balance plan (its COM
/// must come over each stance foot, up to `heavy-correction`), so a walk may fail at 1x and at
/// 0.25x and pass in between. When 1x fails, S is scanned from 1 towards the slowest on a
/// log-spaced grid, fastest first, and the first pass is bisected against the failing S before it;
/// when 1x passes, faster playback is bisected between 1 and the fastest.
struct SpeedSearchOptions {
  double min_time_scale = 0.5;  ///< fastest tried: 2x speed
  double max_time_scale = 4.0;  ///< slowest tried: 0.25x speed
  int scan_steps = 6;           ///< log-spaced S in (1, max_time_scale] tried when 1x fails
  int bisection_steps = 4;      ///< after the bracket is found (log-scale bisection)
};

struct SpeedSearchResult {
  bool feasible = false;       ///< some S in [min, max] passes
  double time_scale = 0;       ///< smallest passing S found (0 when none)
  double speed = 0;            ///< 1 / time_scale: "passes at 0.7x speed"
  bool passes_at_1x = false;
  std::vector<std::pair<double, bool>> trials;  ///< (S, passed) in the order run
};

SpeedSearchResult find_feasible_speed(const Reference& reference, const RobotModel& model, const ValidateRequest& request,
                                      const SpeedSearchOptions& options = {});

/// Runs the check on an in-memory reference (labels contacts first when it has none).
ValidateResult validate_reference(Reference reference, const RobotModel& model, const ValidateRequest& request);

}  // namespace rt
