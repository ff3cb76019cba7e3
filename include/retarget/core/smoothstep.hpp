#pragma once
/// The quintic smoothstep: 0 below 0, 1 above 1, and in between 10x³ − 15x⁴ + 6x⁵, whose first and
/// second derivatives vanish at both ends (a blend that starts and stops without a jerk spike).

#include <algorithm>

namespace rt {

inline double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (10 - 15 * x + 6 * x * x);
}

}  // namespace rt
