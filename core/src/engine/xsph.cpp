#include "engine/xsph.hpp"

#include <cmath>

namespace sphforge {

void xsph_correction(const NeighbourList& nl, KernelKind kernel, double h, double epsilon, const double* x,
                     const double* v, const double* m, const double* rho, double* correction, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double c[3] = {0.0, 0.0, 0.0};
    nl.for_each(i, [&](std::size_t j) {
      const double dx[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
      const double w = kernel_value(kernel, std::sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]), h) * m[j] /
                       (0.5 * (rho[i] + rho[j]));
      for (int d = 0; d < 3; ++d) c[d] += w * (v[3 * j + d] - v[3 * i + d]);
    });
    for (int d = 0; d < 3; ++d) correction[3 * i + d] = epsilon * c[d];
  }
}

}  // namespace sphforge
