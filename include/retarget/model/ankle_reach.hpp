#pragma once
/// Where on each sole the ankle can hold the centre of pressure. A foot's COP can only be as far
/// from its ankle joints' axes as their effort limits allow under the load it carries:
/// |x_cop − x_axis| · F_z ≤ τ_pitch (and the same across the sole for the roll joint). On robots
/// with weak ankles this is well inside the sole: G1's 35 N m ankle pitch holds its 343 N weight
/// only up to 10 cm in front of the axis, whose sole reaches 14 cm, so a plan or a balance
/// controller that puts the COP near the toe asks for 1.4x the ankle's limit and the COM runs
/// past the foot.

#include <array>
#include <string>

#include "retarget/core/types.hpp"

namespace rt {

class RobotModel;

/// Axis-aligned region of a sole in its own frame (x along the length, y across; origin at the
/// sole centre).
struct SoleReach {
  Vec2 min_S = Vec2::Zero(), max_S = Vec2::Zero();  ///< [m]
  std::string pitch_joint, roll_joint;  ///< the joints that bound it ("" when none does)
};

/// The reach of both soles under a normal load of `load_n` each, at the standing pose: the sole
/// rectangle cut, along its length by the first of the foot's two nearest movable joints whose axis
/// lies across the sole (within 30°: ankle pitch), and across it by the first whose axis lies
/// along it (ankle roll); joints without an effort limit do not cut. Never empty: a limit tighter
/// than the sole leaves the point under the axis.
std::array<SoleReach, 2> ankle_reach(const RobotModel& model, double load_n);

/// The whole sole rectangles, uncut (what ankle_reach gives for no load).
std::array<SoleReach, 2> whole_soles(const RobotModel& model);

/// Corners (counter-clockwise seen from above) of `reach` at the sole frame `X_W_sole`.
std::array<Vec3, 4> reach_corners_W(const Iso3& X_W_sole, const SoleReach& reach);

}  // namespace rt
