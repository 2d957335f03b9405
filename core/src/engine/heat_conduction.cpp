#include "engine/heat_conduction.hpp"

#include <cmath>

namespace sphforge {

namespace {

template <KernelKind K>
void heat_conduction_impl(const NeighbourList& nl, double h, const double* x, const double* volume,
                          const double* T, const double* k, double* heat, std::size_t n) {
  // eta^2 = 0.01 h^2 keeps the 1/r^2 finite for coincident particles (eq. 20).
  const double eta2 = 0.01 * h * h;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    double sum = 0.0;
    nl.for_each(i, [&](std::size_t j) {
      const double dx0 = xi[0] - x[3 * j], dx1 = xi[1] - x[3 * j + 1], dx2 = xi[2] - x[3 * j + 2];
      const double r2 = dx0 * dx0 + dx1 * dx1 + dx2 * dx2;
      // x_ij . grad_i W_ij = F(r) r^2 with F = (dW/dr)/r <= 0
      const double xgrad = kernel_gradient_factor(K, std::sqrt(r2), h) * r2;
      const double ksum = k[i] + k[j];
      const double kij = ksum > 0.0 ? 2.0 * k[i] * k[j] / ksum : 0.0;  // eq. 21
      sum += volume[j] * kij * (T[j] - T[i]) * (-2.0 * xgrad) / (r2 + eta2);
    });
    heat[i] += volume[i] * sum;
  }
}

template <KernelKind K>
void surface_area_impl(const NeighbourList& nl, double h, const double* x, const double* volume, double* area,
                       std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double g[3] = {0.0, 0.0, 0.0};
    nl.for_each(i, [&](std::size_t j) {
      const double dx[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
      const double f = volume[j] * kernel_gradient_factor(K, std::sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]), h);
      for (int d = 0; d < 3; ++d) g[d] += f * dx[d];
    });
    area[i] = 2.0 * volume[i] * std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);  // eq. 22
  }
}

}  // namespace

void heat_conduction(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* volume,
                     const double* temperature, const double* conductivity, double* heat_W, std::size_t n) {
  if (kernel == KernelKind::WendlandC2)
    heat_conduction_impl<KernelKind::WendlandC2>(nl, h, x, volume, temperature, conductivity, heat_W, n);
  else
    heat_conduction_impl<KernelKind::CubicSpline>(nl, h, x, volume, temperature, conductivity, heat_W, n);
}

void surface_area(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* volume,
                  double* area, std::size_t n) {
  if (kernel == KernelKind::WendlandC2)
    surface_area_impl<KernelKind::WendlandC2>(nl, h, x, volume, area, n);
  else
    surface_area_impl<KernelKind::CubicSpline>(nl, h, x, volume, area, n);
}

void convection(const double* coefficient, const double* area, const double* temperature, double ambient,
                double* heat_W, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) heat_W[i] += coefficient[i] * area[i] * (ambient - temperature[i]);  // eq. 23
}

}  // namespace sphforge
