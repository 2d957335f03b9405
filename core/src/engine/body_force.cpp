#include "engine/body_force.hpp"

namespace sphforge {

void add_body_force(const double g[3], double mass_scaling, double* acceleration, std::size_t n) {
  // The weight is the physical mass's: the inertial mass is s times larger (eq. 47).
  const double inv_s = 1.0 / mass_scaling;
  const double gx = g[0] * inv_s, gy = g[1] * inv_s, gz = g[2] * inv_s;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    acceleration[3 * i] += gx;
    acceleration[3 * i + 1] += gy;
    acceleration[3 * i + 2] += gz;
  }
}

double body_force_work(const double g[3], double mass_scaling, const double* mass, const double* velocity,
                       std::size_t n, double dt) {
  const double inv_s = 1.0 / mass_scaling;
  const double gx = g[0] * inv_s, gy = g[1] * inv_s, gz = g[2] * inv_s;
  double w = 0.0;
#pragma omp parallel for reduction(+ : w) schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    w += mass[i] * (gx * velocity[3 * i] + gy * velocity[3 * i + 1] + gz * velocity[3 * i + 2]);
  return w * dt;
}

}  // namespace sphforge
