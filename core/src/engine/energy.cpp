#include "engine/energy.hpp"

namespace sphforge {

double kinetic_energy(const double* m, const double* v, std::size_t n) {
  double e = 0.0;
#pragma omp parallel for reduction(+ : e) schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    e += 0.5 * m[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  return e;
}

double internal_work(const double* m, const double* v, const double* a, double dt, std::size_t n) {
  double work = 0.0;
#pragma omp parallel for reduction(+ : work) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double p = 0.0;
    for (int d = 0; d < 3; ++d) p += a[3 * i + d] * (v[3 * i + d] + 0.5 * dt * a[3 * i + d]);
    work -= m[i] * p;
  }
  return dt * work;
}

}  // namespace sphforge
