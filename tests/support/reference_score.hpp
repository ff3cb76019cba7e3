#pragma once
/// Scores a robot reference on the project's kinematic metrics (quality.hpp) with a given contact
/// schedule, so that references from different tools are compared on the same definitions and
/// the same stance phases (the score_reference tool and the LAFAN1 comparison test).

#include <array>
#include <cstdint>
#include <vector>

#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/quality.hpp"
#include "retarget/reference/reference.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt::test {

struct ReferenceScore {
  QualityMetrics feet;          ///< foot_metrics: skating, penetration, frame-0 flatness, ...
  double jitter_rad_s3 = 0;     ///< joint_jitter at the reference's own rate
};

/// `contacts` (T flags per foot, T = the reference's frames) replaces the reference's own schedule.
inline ReferenceScore score_with_contacts(const RobotModel& model, const Reference& ref,
                                          const std::array<std::vector<std::uint8_t>, 2>& contacts) {
  RobotData data(model);
  const MatX q = ReferenceRobotMap(model, ref, "reference").q_all(ref);
  ReferenceScore s;
  s.feet = foot_metrics(model, data, q, ref.fps, contacts);
  s.jitter_rad_s3 = joint_jitter(q, ref.fps);
  return s;
}

}  // namespace rt::test
