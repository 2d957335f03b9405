// Energies of the particle system, for the history and the energy-ledger instability check
// (docs/theory.md, eq. 27).
#pragma once

#include <cstddef>

namespace sphforge {

/// Kinetic energy sum_i m_i |v_i|^2 / 2 (J) of particles [0, n).
double kinetic_energy(const double* mass, const double* velocity, std::size_t n);

/// Work done against the internal forces over one leapfrog step (J): -dt sum_i m_i a_int,i . v_i^n
/// (eq. 27), with a_int the internal (stress, viscosity, artificial stress) acceleration and
/// v^n = v^{n-1/2} + dt a_total / 2 the step-centred velocity. `acceleration` holds a_int + body
/// (the body-force acceleration, already divided by the mass scaling), `contact_force` the contact
/// forces (N; nullptr: none), `velocity` v^{n-1/2}. The centre must use the TOTAL acceleration: with
/// a_int alone, a particle held by a wall (a_contact = -a_int) would book -m dt^2 |a_int|^2 / 2 of
/// spurious work every step, which made the internal energy of extrusion runs negative.
/// Kinetic + internal energy of a free body is conserved by the integrator up to round-off.
double internal_work(const double* mass, const double* velocity, const double* acceleration, const double body[3],
                     const double* contact_force, double dt, std::size_t n);

}  // namespace sphforge
