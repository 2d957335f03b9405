// The SPH operators of the mechanics pipeline, one function per physics term. Equation
// numbers refer to docs/theory.md. Each acts on whole arrays (SoA, OpenMP over particles).
#pragma once

#include <cstddef>

#include "engine/neighbours.hpp"
#include "sphforge/kernels.hpp"

namespace sphforge {

struct ArtificialViscosity {
  double alpha = 1.0;  ///< linear (bulk) term
  double beta = 1.0;   ///< quadratic (von Neumann-Richtmyer) term
  double eta = 0.1;    ///< singularity guard, as a fraction of h
};

/// Velocity gradient L_i = sum_j V_j (v_j - v_i) (x) grad_i W_ij   (theory eq. 3)
/// L stored row-major, 9 per particle, L_ab = dv_a/dx_b.
void velocity_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* v,
                       const double* mass, const double* density, double* L, std::size_t n);

/// Continuity equation: drho_i/dt = -rho_i tr(L_i)   (theory eq. 4)
void continuity_density_rate(const double* L, const double* density, double* density_rate, std::size_t n);

/// Objective (Jaumann) rotation of the deviatoric stress over dt:
/// S <- S + dt (Omega S - S Omega), Omega = (L - L^T)/2   (theory eq. 6)
void jaumann_rotation(const double* L, double dt, double* deviatoric_stress, std::size_t n);

/// Momentum equation, pairwise-symmetric form with Monaghan artificial viscosity:
/// a_i = sum_j m_j [ sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I ] . grad_i W_ij   (theory eqs. 7-8)
/// sigma = S - p I. Because the pair term is antisymmetric in (i, j) and evaluated with the same
/// operands in the same order from both sides, linear momentum is conserved to round-off.
void momentum_rate(const NeighbourList& nl, KernelKind kernel, double h, const ArtificialViscosity& av,
                   double sound_speed, const double* x, const double* v, const double* mass, const double* density,
                   const double* pressure, const double* deviatoric_stress, double* acceleration, std::size_t n);

}  // namespace sphforge
