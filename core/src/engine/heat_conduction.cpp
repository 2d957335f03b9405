#include "engine/heat_conduction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/pair_kernel.hpp"

namespace sphforge {

namespace {

// The two pair passes follow the scheme of engine/pair_kernel.hpp: a per-particle function whose
// neighbour loop is written for `omp simd` (decoded list, scalar accumulator, no branch), run over
// all particles by for_each_particle() in the best instance the CPU has.

template <KernelKind K>
SPHFORGE_PAIR_INLINE double conduction_particle(const NeighbourList& nl, const PairKernel<K>& kernel, double eta2,
                                                const double* x, const double* volume, const double* T,
                                                const double* k, std::size_t i) {
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const double Ti = T[i], ki = k[i];
  const DecodedList list(nl, i);
  const std::uint32_t* const nb = list.indices;
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(list.count);
  double sum = 0.0;
#pragma omp simd reduction(+ : sum)
  for (std::ptrdiff_t c = 0; c < count; ++c) {
    const std::size_t j = nb[c];
    const double dx0 = xi0 - x[3 * j], dx1 = xi1 - x[3 * j + 1], dx2 = xi2 - x[3 * j + 2];
    const double r2 = dx0 * dx0 + dx1 * dx1 + dx2 * dx2;
    // x_ij . grad_i W_ij = F(r) r^2 with F = (dW/dr)/r <= 0
    const double xgrad = kernel.factor(r2) * r2;
    // Harmonic mean (eq. 21); conductivities are >= 0, so a zero sum means both are 0 and the
    // floor only turns 0/0 into 0.
    const double kij = 2.0 * ki * k[j] / std::max(ki + k[j], std::numeric_limits<double>::min());
    sum += volume[j] * kij * (T[j] - Ti) * (-2.0 * xgrad) / (r2 + eta2);
  }
  return volume[i] * sum;
}

template <KernelKind K>
SPHFORGE_PAIR_INLINE double surface_area_particle(const NeighbourList& nl, const PairKernel<K>& kernel,
                                                  const double* x, const double* volume, std::size_t i) {
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const DecodedList list(nl, i);
  const std::uint32_t* const nb = list.indices;
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(list.count);
  double g0 = 0.0, g1 = 0.0, g2 = 0.0;
#pragma omp simd reduction(+ : g0, g1, g2)
  for (std::ptrdiff_t c = 0; c < count; ++c) {
    const std::size_t j = nb[c];
    const double dx0 = xi0 - x[3 * j], dx1 = xi1 - x[3 * j + 1], dx2 = xi2 - x[3 * j + 2];
    const double f = volume[j] * kernel.factor(dx0 * dx0 + dx1 * dx1 + dx2 * dx2);
    g0 += f * dx0, g1 += f * dx1, g2 += f * dx2;
  }
  return 2.0 * volume[i] * std::sqrt(g0 * g0 + g1 * g1 + g2 * g2);  // eq. 22
}

template <KernelKind K>
void heat_conduction_impl(const NeighbourList& nl, double h, const double* x, const double* volume, const double* T,
                          const double* k, double* heat_W, std::size_t n) {
  const PairKernel<K> kernel(h);
  const double eta2 = 0.01 * h * h;  // keeps the 1/r^2 finite for coincident particles (eq. 20)
  for_each_particle(n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
    heat_W[i] += conduction_particle<K>(nl, kernel, eta2, x, volume, T, k, i);
  });
}

template <KernelKind K>
void surface_area_impl(const NeighbourList& nl, double h, const double* x, const double* volume, double* area,
                       std::size_t n) {
  const PairKernel<K> kernel(h);
  for_each_particle(n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
    area[i] = surface_area_particle<K>(nl, kernel, x, volume, i);
  });
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
