// Energies of the particle system, for the history and the energy-ledger instability check
// (docs/theory.md, eq. 26).
#pragma once

#include <cstddef>

namespace sphforge {

/// Kinetic energy sum_i m_i |v_i|^2 / 2 (J) of particles [0, n).
double kinetic_energy(const double* mass, const double* velocity, std::size_t n);

/// Stress power sum_i V_i sigma_i : D_i (W) with sigma = S - p I, D = sym(L), V = m/rho: the rate
/// at which the stresses do work on the deformation (elastic storage plus plastic dissipation).
double stress_power(const double* mass, const double* density, const double* deviatoric_stress,
                    const double* pressure, const double* velocity_gradient, std::size_t n);

}  // namespace sphforge
