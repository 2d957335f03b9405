// Uniform body force (gravity), docs/theory.md eq. 47: a_i += g / s on every mechanical particle,
// s the mass scaling (eq. 24), so that the weight is the physical mass's.
#pragma once

#include <cstddef>

namespace sphforge {

/// Adds g / mass_scaling (m/s^2, 3 components) to the acceleration of particles [0, n).
void add_body_force(const double g[3], double mass_scaling, double* acceleration, std::size_t n);

/// Work of the body force over one step with the step-centred velocities,
/// sum m g . v^{n+1/2} dt / s (J), for the energy ledger (eq. 47).
double body_force_work(const double g[3], double mass_scaling, const double* mass, const double* velocity,
                       std::size_t n, double dt);

}  // namespace sphforge
