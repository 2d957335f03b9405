// XSPH velocity smoothing (Monaghan 1989; docs/theory.md eq. 19): particles move with
//   dx_i/dt = v_i + epsilon sum_j (m_j / rho_ij) (v_j - v_i) W_ij,  rho_ij = (rho_i + rho_j)/2,
// which keeps the lattice orderly in high-speed flow without changing the momentum equation.
#pragma once

#include <cstddef>

#include "engine/neighbours.hpp"
#include "sphforge/kernels.hpp"

namespace sphforge {

/// Writes the XSPH correction epsilon sum_j ... (m/s, 3 per particle) into `correction`.
void xsph_correction(const NeighbourList& nl, KernelKind kernel, double h, double epsilon, const double* x,
                     const double* v, const double* mass, const double* density, double* correction, std::size_t n);

}  // namespace sphforge
