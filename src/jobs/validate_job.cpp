#include "retarget/jobs/validate_job.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/single_support_reach.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/npz_layout.hpp"
#include "retarget/reference/reference_io.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt {

Reference read_reference_for(const RobotModel& model, const std::string& path, double fps,
                             const std::string& joint_order_path) {
  ReferenceReadOptions o;
  if (!joint_order_path.empty()) o.npz_joint_order = read_joint_order(model, joint_order_path);
  o.robot_name = model.name();
  for (int k : model.export_joint_order())
    o.joint_names.push_back(model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(k)])].name);
  o.fps = fps;
  return read_reference(path, o);
}

namespace {

// A schedule the check derived itself is not the reference's claim: its stance feet are not held
// to the reference's floor (the labeller gives a run with no foot down to the lower foot).
DynamicsCheckOptions check_options(const ValidateRequest& request, bool contacts_labelled) {
  DynamicsCheckOptions o = request.check;
  if (contacts_labelled) o.stance_height_tolerance_m = std::numeric_limits<double>::infinity();
  return o;
}

// A failed check of a reference that stands on one foot for a while, on a robot that cannot stand
// on that foot at all (single_support_reach.hpp): say so, it is the reason whatever the controller.
void explain_single_support(const RobotModel& model, const Reference& reference, const DynamicsCheckResult& check,
                            Diagnostics& out, const std::string& where) {
  if (check.passed || !reference.has_contacts() || !(reference.fps > 0)) return;
  const double min_single_support_s = 0.3;  // longer than a walking step's: a hold, not a swing
  std::array<double, 2> longest{{0, 0}};
  for (std::size_t f = 0; f < 2; ++f) {
    const auto& mine = reference.contact[f];
    const auto& other = reference.contact[1 - f];
    int run = 0;
    for (std::size_t i = 0; i < mine.size() && i < other.size(); ++i) {
      run = mine[i] && !other[i] ? run + 1 : 0;
      longest[f] = std::max(longest[f], run / reference.fps);
    }
  }
  if (std::max(longest[0], longest[1]) < min_single_support_s) return;
  const auto reach = single_support_reach(model);
  const char* side[2] = {"left", "right"};
  for (std::size_t f = 0; f < 2; ++f)
    if (longest[f] >= min_single_support_s && reach[f].com_outside_sole_m > 0.005)
      out.warn(where, format("the reference stands on the %s foot alone for up to %.2f s, but %s cannot stand on its %s "
                             "foot: its COM stops %.1f cm outside that sole with the other foot lifted (retarget inspect)",
                             side[f], longest[f], model.name().c_str(), side[f], 100 * reach[f].com_outside_sole_m));
}

}  // namespace

ValidateResult validate_reference(Reference reference, const RobotModel& model, const ValidateRequest& request) {
  ValidateResult r;
  const std::string where = request.reference_path.empty() ? std::string("reference") : request.reference_path;
  if (!reference.has_contacts()) {
    RobotData data(model);
    const ReferenceRobotMap map(model, reference, where);
    const ContactSchedule s =
        label_robot_contacts(model, data, map.q_all(reference), reference.fps, request.contacts, r.diagnostics, where);
    reference.contact = s.in_contact;
    r.contacts_labelled = true;
    r.diagnostics.note(where, "no contact schedule in the file: contacts labelled from the reference's foot heights and speeds");
  }
  r.check = run_dynamics_check(model, reference, check_options(request, r.contacts_labelled));
  explain_single_support(model, reference, r.check, r.diagnostics, where);
  r.reference = std::move(reference);
  return r;
}

ValidateResult run_validate(const ValidateRequest& request, const RobotModel& model) {
  return validate_reference(read_reference_for(model, request.reference_path, request.fps, request.joint_order_path), model, request);
}

SpeedSearchResult find_feasible_speed(const Reference& reference, const RobotModel& model, const ValidateRequest& request,
                                      const SpeedSearchOptions& o) {
  if (!(o.min_time_scale > 0 && o.min_time_scale <= 1 && o.max_time_scale >= 1 && o.scan_steps >= 1 && o.scan_steps <= 100))
    throw InputError("--find-speed", "the time-scale bounds must satisfy 0 < min <= 1 <= max, with 1 to 100 scan steps");
  Reference labelled = reference;
  const bool contacts_labelled = !labelled.has_contacts();
  if (contacts_labelled) labelled = validate_reference(reference, model, request).reference;  // label once
  const DynamicsCheckOptions check = check_options(request, contacts_labelled);
  SpeedSearchResult r;
  auto passes = [&](double S) {
    const bool ok = run_dynamics_check(model, retime_reference(labelled, S), check).passed;
    r.trials.emplace_back(S, ok);
    return ok;
  };
  // Bracket [fail, pass] in S, then bisect in log S.
  double fail = 0, pass = 0;
  r.passes_at_1x = passes(1.0);
  if (r.passes_at_1x) {
    pass = 1.0;
    if (passes(o.min_time_scale)) {
      r.feasible = true;
      r.time_scale = o.min_time_scale;
      r.speed = 1.0 / r.time_scale;
      return r;
    }
    fail = o.min_time_scale;
  } else {
    fail = 1.0;
    for (int k = 1; k <= o.scan_steps && !(pass > 0); ++k) {
      const double S = std::pow(o.max_time_scale, static_cast<double>(k) / o.scan_steps);
      (passes(S) ? pass : fail) = S;
    }
    if (!(pass > 0)) return r;
  }
  for (int i = 0; i < o.bisection_steps; ++i) {
    const double mid = std::sqrt(fail * pass);
    (passes(mid) ? pass : fail) = mid;
  }
  r.feasible = true;
  r.time_scale = pass;
  r.speed = 1.0 / pass;
  return r;
}

}  // namespace rt
