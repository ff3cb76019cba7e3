#pragma once
/// Linear-quadratic regulator design for small dense systems (the balance model is 4 x 4).

#include "retarget/core/types.hpp"

namespace rt {

/// Stabilising solution P of the continuous algebraic Riccati equation
///   Aᵀ P + P A − P B R⁻¹ Bᵀ P + Q = 0
/// from the stable invariant subspace of the Hamiltonian matrix. Throws InternalError when the
/// pair is not stabilisable (no n stable eigenvalues) or the result is not finite.
MatX solve_care(const MatX& A, const MatX& B, const MatX& Q, const MatX& R);

/// State-feedback gain K = R⁻¹ Bᵀ P of the continuous LQR (u = −K x).
MatX lqr_gain(const MatX& A, const MatX& B, const MatX& Q, const MatX& R);

/// Exact zero-order-hold discretisation of ẋ = A x + B u over `dt`: returns (Ad, Bd) with
/// Ad = exp(A dt) and Bd = ∫₀^dt exp(A τ) dτ B.
std::pair<MatX, MatX> discretize_zoh(const MatX& A, const MatX& B, double dt);

}  // namespace rt
