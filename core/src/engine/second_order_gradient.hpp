// Second-order (quadratic-consistent) correction of the velocity gradient and its energy-consistent
// momentum term (theory section 18, eqs. 130-137). Selected by numerics.gradient_correction_order =
// "second"; the first-order correction (eqs. 3a-3b, engine/sph_operators.cpp) stays the default.
//
// Every pair weight of the gradient is g_ij = V_j [W_ij B_i p(x_j - x_i) - F_ij C_i (x_j - x_i)]
// (eq. 133): B_i (3 x 9) from the quadratic moment matrix where it is well conditioned (then
// C_i = 0), else B_i = 0 and C_i the first-order correction (or I where that fails too). One
// formula for both keeps the momentum equation the exact dual of the gradient (eq. 136) in mixed pairs.
#pragma once

#include <cstddef>

#include "engine/neighbours.hpp"
#include "sphforge/kernels.hpp"

namespace sphforge {

/// Largest condition number (1-norm estimate) of the scaled quadratic moment matrix (eq. 131) for
/// which the second-order correction is used; beyond it the particle falls back to first order (eq. 134).
inline constexpr double kSecondOrderMaxCondition = 1e5;

/// Per particle: B_i (27 per particle, row-major 3 x 9, units 1/m: the first three rows of the inverse
/// of the scaled moment matrix, divided by h; eqs. 131-132) and C_i (6 per particle, symmetric
/// xx yy zz xy yz xz, the first-order fallback of eq. 134, 0 where B_i is used). `condition` (may be
/// null): the condition estimate of the quadratic moment matrix where it was used, -1 on fallback.
void second_order_correction(const NeighbourList& nl, KernelKind kernel, double h, const double* x,
                             const double* volume, double* B, double* C, double* condition, std::size_t n);

/// L_i = sum_j (v_j - v_i) (x) g_ij with the pair weights of eq. 133 (row-major, L_ab = dv_a/dx_b):
/// exact for quadratic velocity fields wherever B_i is used (eq. 132).
void second_order_velocity_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x,
                                    const double* v, const double* volume, const double* B, const double* C,
                                    double* L, std::size_t n);

/// A_i = sigma_i B_i (27 per particle, row-major 3 x 9), sigma = S - p I: the per-particle factor of
/// the momentum term (eq. 136).
void second_order_stress(const double* pressure, const double* deviatoric_stress, const double* B, double* stress_b,
                         std::size_t n);

/// Adds the quadratic part of the momentum equation dual to the gradient of eq. 133 (eq. 136):
/// a_i += V_i/m_i sum_j V_j W_ij [(A_i' + A_j') d/h + (A_i'' - A_j'') q(d)/h^2], d = x_j - x_i,
/// A' the first three columns of A = sigma B, A'' the other six. The pair forces are antisymmetric.
void second_order_momentum_term(const NeighbourList& nl, KernelKind kernel, double h, const double* x,
                                const double* mass, const double* volume, const double* stress_b,
                                double* acceleration, std::size_t n);

}  // namespace sphforge
