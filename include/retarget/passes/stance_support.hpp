#pragma once
/// The support polygon a motion frame stands on: the convex hull, in the floor plane, of the sole
/// rectangles (robot.yaml `feet`) of the feet labelled in contact, where the kinematics put them.
/// Shared by the COM plan and the ZMP metric, so both judge against the same polygon.

#include <array>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/model/ankle_reach.hpp"

namespace rt {

class RobotModel;
class RobotData;

/// At the configuration last given to update_kinematics; empty when no foot is down.
SupportPolygon stance_support_polygon(const RobotModel& model, const RobotData& data, const std::array<bool, 2>& down);

/// The same with each sole cut to `reach` (ankle_reach.hpp: where its ankle can hold the COP), the
/// support a plan may use; the metric keeps the whole soles.
SupportPolygon stance_support_polygon(const RobotModel& model, const RobotData& data, const std::array<bool, 2>& down,
                                      const std::array<SoleReach, 2>& reach);

}  // namespace rt
