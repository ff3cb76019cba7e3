#include "retarget/sim/reference_consistency.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/strings.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/torque_demand.hpp"
#include "retarget/sim/reference_signal.hpp"

namespace rt {

namespace {

// The first frame a reference-side check judges: the standing lead-in of `lead_s` is the check's
// own motion, not the reference's, so from the clip's second frame on (the first one's central
// difference reaches into the lead-in); from frame 0 without a lead-in.
int first_judged_frame(const ReferenceSignal& signal, double lead_s) {
  return lead_s > 0 ? static_cast<int>(std::lround(lead_s * signal.fps())) + 1 : 0;
}

}  // namespace

std::vector<Violation> stance_off_floor(const ReferenceSignal& signal, double lead_s, double tolerance_m) {
  const auto& soles = signal.soles_W();
  const auto& contacts = signal.contacts();
  // The standing lead-in is the check's own motion, not the reference's: judged from frame 0 on.
  const std::size_t first = static_cast<std::size_t>(std::max(0L, std::lround(lead_s * signal.fps())));
  std::vector<double> heights;
  for (std::size_t f = 0; f < 2; ++f)
    for (std::size_t k = first; k < contacts[f].size(); ++k)
      if (contacts[f][k]) heights.push_back(soles[f][k].translation().z());
  std::vector<Violation> out;
  if (heights.empty()) return out;
  const auto mid = heights.begin() + static_cast<std::ptrdiff_t>(heights.size() / 2);
  std::nth_element(heights.begin(), mid, heights.end());
  const double floor_z = *mid;
  static const char* const foot_name[2] = {"left foot", "right foot"};
  for (std::size_t f = 0; f < 2; ++f) {
    ViolationTracker tracker(ViolationKind::StanceOffFloor, "m", 0.0);
    const std::size_t T = contacts[f].size();
    for (std::size_t k = first; k < T; ++k) {
      const double t = static_cast<double>(k) / signal.fps() - lead_s;
      const double dz = soles[f][k].translation().z() - floor_z;
      const bool off = contacts[f][k] && std::abs(dz) > tolerance_m;
      tracker.update(t, off, std::abs(dz),
                     off ? format("the reference labels the %s in contact %.3f m %s its floor (z = %.3f m, the median of its "
                                  "stance soles)",
                                  foot_name[f], std::abs(dz), dz > 0 ? "above" : "below", floor_z)
                         : "",
                     out);
    }
    tracker.finish(static_cast<double>(T) / signal.fps() - lead_s, out);
  }
  return out;
}

std::vector<Violation> reference_joint_speed(const RobotModel& model, const ReferenceSignal& signal, double lead_s) {
  std::vector<Violation> out;
  ViolationTracker tracker(ViolationKind::JointVelocity, "ratio", 0.0);
  const VecX& vmax = model.velocity_limits();
  const int nu = model.nu(), T = signal.num_frames();
  for (int k = first_judged_frame(signal, lead_s); k < T; ++k) {
    const double t = k / signal.fps();
    const VecX v = signal.at(t, TrunkTransform{}).v.tail(nu);
    double worst = 0;
    int joint = -1;
    for (int i = 0; i < nu; ++i)
      if (vmax[i] > 0 && std::abs(v[i]) / vmax[i] > worst) {
        worst = std::abs(v[i]) / vmax[i];
        joint = i;
      }
    const bool fast = worst > 1;
    tracker.update(t - lead_s, fast, worst,
                   fast ? format("the reference moves %s at %.2fx its velocity limit (%.3g /s)",
                                 model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(joint)])].name.c_str(),
                                 worst, vmax[joint])
                        : "",
                   out);
  }
  tracker.finish(T / signal.fps() - lead_s, out);
  return out;
}

std::vector<Violation> reference_torque_demand(const RobotModel& model, RobotData& data, const ReferenceSignal& signal, double lead_s) {
  std::vector<Violation> out;
  const TorqueDemand d = torque_demand(model, data, signal.q_frames(), signal.fps());
  if (d.frames == 0) return out;
  ViolationTracker tracker(ViolationKind::ReferenceTorque, "ratio", 0.0);
  const int T = signal.num_frames();
  for (int k = std::max(first_judged_frame(signal, lead_s), 1); k + 1 < T; ++k) {  // the ends have no demand
    const double ratio = d.frame_max_ratio[static_cast<std::size_t>(k)];
    const int joint = d.frame_max_joint[static_cast<std::size_t>(k)];
    const bool over = ratio > 1 && joint >= 0;
    tracker.update(k / signal.fps() - lead_s, over, ratio,
                   over ? format("the reference asks %s for %.2fx its effort limit (%.3g N m; inverse dynamics of its frames)",
                                 model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(joint)])].name.c_str(),
                                 ratio, model.effort_limits()[joint])
                        : "",
                   out);
  }
  tracker.finish((T - 1) / signal.fps() - lead_s, out);
  return out;
}

}  // namespace rt
