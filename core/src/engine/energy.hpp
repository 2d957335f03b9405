// Energies of the particle system, for the history and the energy-ledger instability check
// (docs/theory.md, eq. 27).
#pragma once

#include <cstddef>

namespace sphforge {

/// Kinetic energy sum_i m_i |v_i|^2 / 2 (J) of particles [0, n).
double kinetic_energy(const double* mass, const double* velocity, std::size_t n);

/// Work done against the internal forces over one leapfrog step (J): -dt sum_i m_i a_i . v_i^n with
/// a the internal (stress, viscosity, artificial stress) acceleration and v^n = v^{n-1/2} + dt a / 2
/// the step-centred velocity, so that kinetic + internal energy of a free body is conserved by the
/// integrator up to round-off (eq. 27). `velocity` holds v^{n-1/2}.
double internal_work(const double* mass, const double* velocity, const double* acceleration, double dt,
                     std::size_t n);

}  // namespace sphforge
