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

#include "sphforge/bond_rule.hpp"

namespace sphforge {

/// Inputs of the pair rule, for the pair passes (null `failed`: no failure in the scene, and the
/// passes run the loops without the rule).
struct BondFailure {
  const double* failed = nullptr;  ///< 1 per particle: 1 failed, 0 intact (eq. 110)
  const double* stress = nullptr;  ///< 6 per particle: Cauchy stress sigma = S - p I at the step's start, Pa
};

// bond_factor(), k_ij of eq. 112, is public (sphforge/bond_rule.hpp): processes read the same rule.

/// The rule for particle i's pairs inside a pair pass: loads i's stress and flag once, outside the
/// neighbour loop. Failure = false (no failure in the scene) compiles to a factor 1, so the loops
/// run without the rule.
template <bool Failure>
struct BondRule {
  const BondFailure& failure;
  double sigma_i[6] = {0, 0, 0, 0, 0, 0}, failed_i = 0.0;
  __attribute__((always_inline)) BondRule(const BondFailure& f, std::size_t i) : failure(f) {
    if constexpr (Failure) {
      for (int c = 0; c < 6; ++c) sigma_i[c] = f.stress[6 * i + c];
      failed_i = f.failed[i];
    }
  }
  /// k_ij (eq. 112) for the pair (i, j), x_ij = x_i - x_j.
  __attribute__((always_inline)) double factor(std::size_t j, double x0, double x1, double x2) const {
    if constexpr (Failure) return bond_factor(failed_i, failure.failed[j], sigma_i, failure.stress + 6 * j, x0, x1, x2);
    return 1.0;
  }
};

/// sigma_i = S_i - p_i I (6 per particle, xx yy zz xy yz xz), the stress the pair rule reads.
void cauchy_stress(const double* pressure, const double* deviatoric_stress, double* sigma, std::size_t n);

}  // namespace sphforge
