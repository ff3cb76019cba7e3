#include "retarget/sim/reference_consistency.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/strings.hpp"
#include "retarget/sim/reference_signal.hpp"

namespace rt {

std::vector<Violation> stance_off_floor(const ReferenceSignal& signal, double lead_s, double tolerance_m) {
  const auto& soles = signal.soles_W();
  const auto& contacts = signal.contacts();
  std::vector<double> heights;
  for (std::size_t f = 0; f < 2; ++f)
    for (std::size_t k = 0; k < contacts[f].size(); ++k)
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
    for (std::size_t k = 0; k < T; ++k) {
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

}  // namespace rt
