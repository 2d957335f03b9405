// Bond failure: the pair rule that lets material separate without deleting particles
// (docs/theory.md section 16, eqs. 110-115; docs/failure.md).
//
// A particle is `failed` once its material says so (its equivalent plastic strain reached the
// material's failure_plastic_strain, eq. 110; the flag is latched). A pair of two failed particles
// is a broken bond (eq. 111). A broken bond transmits nothing while the pair is under tension and
// everything (stress, its shear included) while it is under compression (eq. 112): so a crack
// opens where the material is pulled apart, while failed material that is still pressed together
// (the stir zone under a drill) keeps its strength. The same factor removes the pair from the
// velocity gradient (and the correction matrix and the continuity equation that use it) and from
// the stress and artificial-stress terms of the momentum equation, so that the energy consistency
// of eq. 7 holds for the pairs that remain (eq. 113).
#pragma once

#include <cstddef>

namespace sphforge {

/// Inputs of the pair rule, for the pair passes (null `failed`: no failure in the scene, and the
/// passes run the loops without the rule).
struct BondFailure {
  const double* failed = nullptr;  ///< 1 per particle: 1 failed, 0 intact (eq. 110)
  const double* stress = nullptr;  ///< 6 per particle: Cauchy stress sigma = S - p I at the step's start, Pa
};

/// k_ij of eq. 112 for the pair (i, j) with x_ij = xi - xj: 0 when both particles failed and the
/// pair's normal stress t_ij = x_ij . (sigma_i + sigma_j) . x_ij is tensile (> 0), else 1. Symmetric
/// in i and j (t_ij is a quadratic form in x_ij), so the pair forces stay antisymmetric. Written
/// without branches for the vectorised pair loops.
__attribute__((always_inline)) inline double bond_factor(double failed_i, double failed_j, const double* sigma_i,
                                                         const double* sigma_j, double x0, double x1, double x2) {
  const double t = (sigma_i[0] + sigma_j[0]) * x0 * x0 + (sigma_i[1] + sigma_j[1]) * x1 * x1 +
                   (sigma_i[2] + sigma_j[2]) * x2 * x2 +
                   2.0 * ((sigma_i[3] + sigma_j[3]) * x0 * x1 + (sigma_i[4] + sigma_j[4]) * x1 * x2 +
                          (sigma_i[5] + sigma_j[5]) * x0 * x2);
  const double broken = failed_i * failed_j;  // eq. 111: 1 only when both failed
  return 1.0 - broken * (t > 0.0 ? 1.0 : 0.0);
}

/// sigma_i = S_i - p_i I (6 per particle, xx yy zz xy yz xz), the stress the pair rule reads.
void cauchy_stress(const double* pressure, const double* deviatoric_stress, double* sigma, std::size_t n);

}  // namespace sphforge
