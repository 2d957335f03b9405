// Heat conduction between particles and convection on free surfaces (docs/theory.md,
// section 4, eqs. 20-23). Acts on whole arrays; OpenMP over particles.
#pragma once

#include <cstddef>

#include "engine/neighbours.hpp"
#include "sphforge/kernels.hpp"

namespace sphforge {

/// Cleary-Monaghan conduction (eq. 20): the heat flowing into particle i (W),
///   Q_i = sum_j V_i V_j k_ij (T_j - T_i) 2 (-x_ij . grad_i W_ij) / (r_ij^2 + eta^2),
///   k_ij = 2 k_i k_j / (k_i + k_j)   (harmonic mean, eq. 21),
/// with V = m/rho. Every pair term is antisymmetric in (i, j), so the heat one particle loses
/// its neighbour gains, across bodies and materials alike. Adds to `heat_W`.
/// `h_point` (default null): per-particle smoothing lengths of a scene of several spacings (eq. 138).
void heat_conduction(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* volume,
                     const double* temperature, const double* conductivity, double* heat_W, std::size_t n,
                     const double* h_point = nullptr);

/// Free-surface area carried by each particle (m^2, eq. 22): A_i = 2 V_i |sum_j V_j grad_i W_ij|.
/// The kernel sum S = sum_j V_j W_ij falls from 1 inside a body to 1/2 at its surface, so its
/// gradient integrated over the particles inside gives half the surface area; the factor 2
/// restores it. Zero in the interior and at interfaces between bodies (their neighbours count).
void surface_area(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* volume,
                  double* area, std::size_t n, const double* h_point = nullptr);

/// Newton convection (eq. 23): Q_i += h_i A_i (T_ambient - T_i). Adds to `heat_W`.
void convection(const double* coefficient, const double* area, const double* temperature, double ambient,
                double* heat_W, std::size_t n);

}  // namespace sphforge
