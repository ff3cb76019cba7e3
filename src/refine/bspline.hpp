#pragma once
/// Uniform cubic B-splines over source frames (private to rt_refine).
///
/// A trajectory x(t) in chart coordinates (trajectory_chart.hpp) is Σ_j B_j(t) C_j with control
/// points C_j, j = 0..N-1, and the knot spacing `stride` source frames: source frame f sits at
/// t = f / stride, and knot k (t = k) is (C_k + 4 C_{k+1} + C_{k+2}) / 6. N = K + 2 control points
/// cover K knots. Two properties make the refine pass's guarantees exact at every source frame:
///  - convex hull: x(t) is a convex combination of 4 control points, so control points inside the
///    joint limits give a curve inside them;
///  - ẋ(t) is a quadratic B-spline with control points (C_{j+1} − C_j) / h (h: seconds per
///    segment), so |C_{j+1} − C_j| ≤ v_max h bounds |ẋ| everywhere, hence also every finite
///    difference between source frames.

#include <array>

#include "retarget/core/types.hpp"

namespace rt::refine {

/// The control points that shape the curve at one parameter value, with their weights (zero
/// weights dropped: 3 at a knot, 4 in between).
struct SplineSupport {
  int count = 0;
  std::array<int, 4> index{};
  std::array<double, 4> weight{};
  std::array<double, 4> dweight{};  ///< d(weight)/dt: the curve's derivative per knot interval
};

/// Support at parameter t (knot units, 0 <= t <= num_controls − 3).
SplineSupport spline_support(double t, int num_controls);

/// Number of control points for T source frames at a stride: K = ceil((T − 1) / stride) + 1 knots.
int spline_num_controls(int num_frames, int stride);

/// Curve value at t: Σ weights · columns of `controls` (dim x N).
VecX spline_value(const MatX& controls, double t);

/// Least-squares fit of control points (dim x N) to samples (dim x T, one per source frame), with a
/// small penalty `smoothing` on second differences of the control points (keeps the end points
/// determined when the last segment holds few samples).
MatX spline_fit(const MatX& samples, int stride, double smoothing = 1e-6);

}  // namespace rt::refine
