#include "engine/energy.hpp"

namespace sphforge {

double kinetic_energy(const double* m, const double* v, std::size_t n) {
  double e = 0.0;
#pragma omp parallel for reduction(+ : e) schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    e += 0.5 * m[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  return e;
}

double internal_work(const double* m, const double* v, const double* a, const double body[3],
                     const double* contact_force, double dt, std::size_t n) {
  double work = 0.0;
#pragma omp parallel for reduction(+ : work) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double inv_m = 1.0 / m[i];
    double p = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double internal = a[3 * i + d] - body[d];
      const double total = a[3 * i + d] + (contact_force ? contact_force[3 * i + d] * inv_m : 0.0);
      p += internal * (v[3 * i + d] + 0.5 * dt * total);
    }
    work -= m[i] * p;
  }
  return dt * work;
}

}  // namespace sphforge
