// The pair rule of bond failure (docs/theory.md eqs. 111-112, docs/failure.md), public so that a
// plugin can ask which pairs the core treats as separated without restating the rule (the
// friction-drilling bushing's connectivity, theory eq. 127a). The core's pair passes use this
// same function (core/src/engine/bond_failure.hpp).
#pragma once

namespace sphforge {

/// k_ij of eq. 112 for the pair (i, j) with x_ij = xi - xj: 0 when both particles failed and the
/// pair's normal stress t_ij = x_ij . (sigma_i + sigma_j) . x_ij is tensile (> 0), else 1. Symmetric
/// in i and j (t_ij is a quadratic form in x_ij), so the pair forces stay antisymmetric. Written
/// without branches for the vectorised pair loops. `sigma_i`, `sigma_j`: Cauchy stresses
/// sigma = S - p I, 6 components each (xx yy zz xy yz xz), Pa; `failed_i`, `failed_j`: the field
/// `failed` (1 failed, 0 intact).
__attribute__((always_inline)) inline double bond_factor(double failed_i, double failed_j, const double* sigma_i,
                                                         const double* sigma_j, double x0, double x1, double x2) {
  const double t = (sigma_i[0] + sigma_j[0]) * x0 * x0 + (sigma_i[1] + sigma_j[1]) * x1 * x1 +
                   (sigma_i[2] + sigma_j[2]) * x2 * x2 +
                   2.0 * ((sigma_i[3] + sigma_j[3]) * x0 * x1 + (sigma_i[4] + sigma_j[4]) * x1 * x2 +
                          (sigma_i[5] + sigma_j[5]) * x0 * x2);
  const double broken = failed_i * failed_j;  // eq. 111: 1 only when both failed
  return 1.0 - broken * (t > 0.0 ? 1.0 : 0.0);
}

}  // namespace sphforge
