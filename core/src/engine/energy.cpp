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

ConstraintEnergy constraint_energy(const double* m, const double* v_pred, const double* a_tot, const double* v,
                                   const double* a, const double body[3], const double* fc, double dt,
                                   std::size_t n) {
  double work = 0.0, correction = 0.0;
#pragma omp parallel for reduction(+ : work, correction) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double dv[3], centre[3], a_int[3];
    bool changed = false;
    for (int d = 0; d < 3; ++d) {
      const std::size_t k = 3 * i + d;
      const double v_new = v[k] + dt * a[k];
      dv[d] = v_new - v_pred[k];
      changed = changed || dv[d] != 0.0;
      centre[d] = 0.5 * (v_pred[k] - dt * a_tot[k] + v_new);  // (v^{n-1/2} + v^{n+1/2}) / 2
      a_int[d] = a_tot[k] - body[d] - (fc ? fc[k] / m[i] : 0.0);
    }
    if (!changed) continue;
    // Eq. 27a: the constraint's impulse m dv does work at the step's centre velocity, and the
    // internal force's work moves from the predicted centre to the true one, -dt m a_int . dv / 2.
    for (int d = 0; d < 3; ++d) {
      work += m[i] * dv[d] * centre[d];
      correction -= 0.5 * dt * m[i] * a_int[d] * dv[d];
    }
  }
  return {work, correction};
}

}  // namespace sphforge
