#pragma once
/// The balance model of paper §IV-A / design.md §3.4: per horizontal axis a point mass at the COM
/// on a mobile base whose position is the COP,
///
///     c̈ = ω² (c − p),   p̈ = a,   ω² = g / z_c,     state s = (c, p, ċ, ṗ), input a.
///
/// The 3-D pendulum decouples into x and y when linearised, so both axes share these matrices.

#include "retarget/core/types.hpp"

namespace rt {

struct PendulumModel {
  double com_height_m = 0.8;   ///< z_c: COM height of the robot's standing pose
  double gravity = 9.81;       ///< [m/s^2]

  double omega_sq() const { return gravity / com_height_m; }
  /// Continuous state matrix (4 x 4) for s = (c, p, ċ, ṗ).
  Mat4 A() const;
  /// Continuous input matrix (4 x 1) for the base acceleration a.
  Vec4 B() const;
  /// Equilibrium for a COM reference: s_ref = E c_ref with E = (1, 1, 0, 0).
  static Vec4 E() { return Vec4(1, 1, 0, 0); }
};

}  // namespace rt
