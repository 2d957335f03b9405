// delta-SPH density diffusion (Antuono, Colagrossi, Marrone, Molteni 2010, "Free-surface flows solved
// by means of SPH schemes with numerical diffusive terms", Comput. Phys. Commun. 181:532-549):
// docs/theory.md eqs. 4a-4b. Optional (`numerics.density_diffusion`, delta; 0: off, no pass, no memory).
//
// Why: the continuity equation (eq. 4) integrates the density from the velocity divergence, so its
// errors accumulate; nothing ties rho back to where the particles are. Where a nearly incompressible
// body is sheared hard for a long time (the paste under the ram's centre, K / sigma_y ~ 800), the
// density drifts into layers of -15 % and +15 %: pressures of -50 and +50 MPa next to each other
// under a 5 MPa extrusion pressure, and in a sector run an exit 3 (docs/stability.md, last section).
// The term diffuses that noise; with the corrected-gradient part it is zero for a density that is
// linear in space, so a steady pressure gradient (the extrusion pressure falling towards the die)
// does not drive a flux. Its coefficient delta h c grows as the mass scaling falls; where the
// density is far from linear it then acts as a volume source (docs/validation/ram_extrusion.md 1a).
#pragma once

#include <cstddef>

#include "engine/bond_failure.hpp"
#include "engine/neighbours.hpp"
#include "sphforge/kernels.hpp"

namespace sphforge {

/// Corrected density gradient g_i = C_i sum_j V_j (rho_j - rho_i) grad_i W_ij (eq. 4b), 3 per
/// particle, for the n real particles. C (6 per particle, symmetric, from velocity_gradient()) may be
/// null: C = I. The lists may reach ghosts (j >= n), whose x, rho and V are in the extended arrays.
void density_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* rho,
                      const double* volume, const double* correction, double* gradient, std::size_t n,
                      const BondFailure& failure = {});

/// Diffusive density rate (eq. 4a), added to `density_rate` (n real particles):
///   D_i = delta h c sum_j V_j psi_ij . grad_i W_ij,
///   psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / |x_ij|^2 - (g_i + g_j),
/// with grad_i W_ij = F(r) (x_i - x_j) written without the division by |x_ij|^2:
///   psi_ij . grad_i W_ij = -F (2 (rho_j - rho_i) + (g_i + g_j) . (x_i - x_j)).
/// `gradient` holds g for the real particles and the ghosts (3 per particle).
void add_density_diffusion(const NeighbourList& nl, KernelKind kernel, double h, double delta, double wave_speed,
                           const double* x, const double* rho, const double* volume, const double* gradient,
                           double* density_rate, std::size_t n, const BondFailure& failure = {});

}  // namespace sphforge
