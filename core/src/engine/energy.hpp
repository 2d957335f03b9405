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

/// What a process's velocity constraints (clamps, pistons: Process::apply_constraints) change in the
/// energy ledger over one step (eq. 27a).
struct ConstraintEnergy {
  double work_J = 0.0;                       ///< work the constraints do on the particles
  double internal_energy_correction_J = 0.0; ///< to add to the step's internal_work()
};

/// `predicted_velocity` v^{n-1/2} + dt a_total and `total_acceleration` a_total (3 per particle)
/// as they were before the constraints; `velocity` and `acceleration` after them, so that
/// v^{n+1/2} = velocity + dt acceleration. internal_work() centred a constrained particle's step on
/// the velocity the integrator would have given; its true centre is (v^{n-1/2} + v^{n+1/2}) / 2.
/// Without the correction a clamped particle (v = 0, a = 0) books -m dt^2 |a_int|^2 / 2 of
/// internal energy every step: a clamped cantilever's internal energy went to -21 times its
/// initial kinetic energy in 0.3 s. Unconstrained particles contribute nothing.
ConstraintEnergy constraint_energy(const double* mass, const double* predicted_velocity,
                                   const double* total_acceleration, const double* velocity,
                                   const double* acceleration, const double body[3], const double* contact_force,
                                   double dt, std::size_t n);

}  // namespace sphforge
