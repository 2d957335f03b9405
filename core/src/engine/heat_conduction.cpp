#include "engine/heat_conduction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/pair_kernel.hpp"

namespace sphforge {

namespace {

// eta^2 / h^2 of eq. 20: keeps the 1/r^2 finite for coincident particles.
constexpr double kConductionEta2 = 0.01;

// The two pair passes follow the scheme of engine/pair_kernel.hpp: a per-particle function whose
// neighbour loop is written for `omp simd` (decoded list, scalar accumulator, no branch), run over
// all particles by for_each_particle() in the best instance the CPU has.

// Variable: per-particle smoothing lengths h_point (eq. 138), the pair's kernel and eta at h_ij.
template <KernelKind K, bool Variable>
SPHFORGE_PAIR_INLINE double conduction_particle(const NeighbourList& nl, const PairKernel<K>& kernel, double eta2,
                                                const double* h_point, const double* x, const double* volume,
                                                const double* T, const double* k, std::size_t i) {
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const double hi = Variable ? h_point[i] : 0.0;
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
    double xgrad, eta2_ij = eta2;
    if constexpr (Variable) {
      const double hij = pair_smoothing_length(hi, h_point[j]);
      xgrad = kernel.factor_at(r2, hij) * r2;
      eta2_ij = kConductionEta2 * hij * hij;
    } else {
      xgrad = kernel.factor(r2) * r2;
    }
    // Harmonic mean (eq. 21); conductivities are >= 0, so a zero sum means both are 0 and the
    // floor only turns 0/0 into 0.
    const double kij = 2.0 * ki * k[j] / std::max(ki + k[j], std::numeric_limits<double>::min());
    sum += volume[j] * kij * (T[j] - Ti) * (-2.0 * xgrad) / (r2 + eta2_ij);
  }
  return volume[i] * sum;
}

template <KernelKind K, bool Variable>
SPHFORGE_PAIR_INLINE double surface_area_particle(const NeighbourList& nl, const PairKernel<K>& kernel,
                                                  const double* h_point, const double* x, const double* volume,
                                                  std::size_t i) {
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const double hi = Variable ? h_point[i] : 0.0;
  const DecodedList list(nl, i);
  const std::uint32_t* const nb = list.indices;
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(list.count);
  double g0 = 0.0, g1 = 0.0, g2 = 0.0;
#pragma omp simd reduction(+ : g0, g1, g2)
  for (std::ptrdiff_t c = 0; c < count; ++c) {
    const std::size_t j = nb[c];
    const double dx0 = xi0 - x[3 * j], dx1 = xi1 - x[3 * j + 1], dx2 = xi2 - x[3 * j + 2];
    const double r2 = dx0 * dx0 + dx1 * dx1 + dx2 * dx2;
    double kf;
    if constexpr (Variable) kf = kernel.factor_at(r2, pair_smoothing_length(hi, h_point[j]));
    else kf = kernel.factor(r2);
    const double f = volume[j] * kf;
    g0 += f * dx0, g1 += f * dx1, g2 += f * dx2;
  }
  return 2.0 * volume[i] * std::sqrt(g0 * g0 + g1 * g1 + g2 * g2);  // eq. 22
}

template <KernelKind K>
void heat_conduction_impl(const NeighbourList& nl, double h, const double* x, const double* volume, const double* T,
                          const double* k, double* heat_W, std::size_t n, const double* h_point) {
  const PairKernel<K> kernel(h);
  const double eta2 = kConductionEta2 * h * h;
  if (h_point)
    for_each_particle(n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
      heat_W[i] += conduction_particle<K, true>(nl, kernel, eta2, h_point, x, volume, T, k, i);
    });
  else
    for_each_particle(n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
      heat_W[i] += conduction_particle<K, false>(nl, kernel, eta2, nullptr, x, volume, T, k, i);
    });
}

template <KernelKind K>
void surface_area_impl(const NeighbourList& nl, double h, const double* x, const double* volume, double* area,
                       std::size_t n, const double* h_point) {
  const PairKernel<K> kernel(h);
  if (h_point)
    for_each_particle(n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
      area[i] = surface_area_particle<K, true>(nl, kernel, h_point, x, volume, i);
    });
  else
    for_each_particle(n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
      area[i] = surface_area_particle<K, false>(nl, kernel, nullptr, x, volume, i);
    });
}

}  // namespace

void heat_conduction(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* volume,
                     const double* temperature, const double* conductivity, double* heat_W, std::size_t n,
                     const double* h_point) {
  if (kernel == KernelKind::WendlandC2)
    heat_conduction_impl<KernelKind::WendlandC2>(nl, h, x, volume, temperature, conductivity, heat_W, n, h_point);
  else
    heat_conduction_impl<KernelKind::CubicSpline>(nl, h, x, volume, temperature, conductivity, heat_W, n, h_point);
}

void surface_area(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* volume,
                  double* area, std::size_t n, const double* h_point) {
  if (kernel == KernelKind::WendlandC2)
    surface_area_impl<KernelKind::WendlandC2>(nl, h, x, volume, area, n, h_point);
  else
    surface_area_impl<KernelKind::CubicSpline>(nl, h, x, volume, area, n, h_point);
}

void convection(const double* coefficient, const double* area, const double* temperature, double ambient,
                double* heat_W, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) heat_W[i] += coefficient[i] * area[i] * (ambient - temperature[i]);  // eq. 23
}

}  // namespace sphforge
