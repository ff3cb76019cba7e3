#pragma once
/// Sole frames on a flat floor, shared by the check (its controllers and monitor) and com-plan.

#include <array>

#include "retarget/core/types.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

/// Corners of a sole rectangle at the sole frame `X_W_sole` (x forward, z normal, at its centre).
std::array<Vec3, 4> sole_corners_W(const Iso3& X_W_sole, const Sole& sole);

/// The same sole frame laid flat on the floor (z = 0), keeping its heading.
Iso3 flat_on_floor(const Iso3& X_W_sole);

/// A foot's actual sole frame (at its centre) at `data`'s kinematics; R_L_sole: the sole frame in
/// the foot link (sole_frames_in_links).
Iso3 sole_frame_W(const RobotModel& model, const RobotData& data, int foot, const Mat3& R_L_sole);

}  // namespace rt
