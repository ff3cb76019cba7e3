#pragma once
/// Zero-phase Gaussian low-pass of sampled signals (columns are samples), truncated at 3σ, with the
/// end samples repeated beyond the ends. σ = 0.03 s halves an amplitude at about 6 Hz
/// (gain exp(−2π²σ²f²)).

#include "retarget/core/types.hpp"

namespace rt {

/// Each row of `x` (one signal, columns = samples) filtered with standard deviation `sigma_samples`;
/// σ ≤ 1e-3 returns x unchanged.
MatX gaussian_filter(const MatX& x, double sigma_samples);

}  // namespace rt
