#pragma once
/// Time derivatives of a sampled horizontal COM trajectory, for the balance controller's
/// feed-forward (balance_controller.hpp: s_ref and a_ref need ċ … c⁗). Shared by the dynamics check
/// (reference COM at the clip's frame rate) and the com-replan pass (on the planner grid), so that
/// the offline preview and the online controller track the same reference.

#include <array>

#include "retarget/core/types.hpp"

namespace rt {

/// ċ, c̈, c⃛, c⁗ [m/s … m/s⁴] of `com_W` (2 x T, uniform samples at `rate_hz`), per sample.
/// The trajectory is first smoothed by a zero-phase Gaussian of standard deviation `smoothing_s`
/// [s] (0 = none): the fourth derivative of a 30 fps trajectory amplifies 0.1 mm of jitter to
/// metres per second⁴. The ends are padded with the first and last sample (a clip is held there),
/// and each derivative is a central difference of the previous one (one-sided at the ends).
/// Throws InputError unless 0 <= smoothing_s <= 10 and rate_hz > 0.
std::array<Eigen::Matrix2Xd, 4> com_derivatives(const Eigen::Matrix2Xd& com_W, double rate_hz, double smoothing_s);

}  // namespace rt
