#include "engine/energy.hpp"

namespace sphforge {

double kinetic_energy(const double* m, const double* v, std::size_t n) {
  double e = 0.0;
#pragma omp parallel for reduction(+ : e) schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    e += 0.5 * m[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  return e;
}

double stress_power(const double* m, const double* rho, const double* S, const double* p, const double* L,
                    std::size_t n) {
  double power = 0.0;
#pragma omp parallel for reduction(+ : power) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double* l = L + 9 * i;
    const double* s = S + 6 * i;
    // S : D with the symmetric part of L (shear terms counted twice), minus p tr(D)   (eq. 26)
    const double s_d = s[0] * l[0] + s[1] * l[4] + s[2] * l[8] + s[3] * (l[1] + l[3]) + s[4] * (l[5] + l[7]) +
                       s[5] * (l[2] + l[6]);
    power += m[i] / rho[i] * (s_d - p[i] * (l[0] + l[4] + l[8]));
  }
  return power;
}

}  // namespace sphforge
