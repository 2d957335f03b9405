#include "engine/density_diffusion.hpp"

#include "engine/pair_kernel.hpp"

namespace sphforge {

namespace {

struct DiffusionArgs {
  const NeighbourList* nl;
  const double *x, *rho, *volume, *correction, *gradient;
  double* out;
  std::size_t n;
  double coefficient;   // delta h c (eq. 4a)
  BondFailure failure;  // failed == null: no failure in the scene
};

// A broken bond under tension (eq. 112, BondRule in bond_failure.hpp) carries no density flux
// either, as it carries no velocity gradient (eq. 113).

// g_i of eq. 4b.
template <KernelKind K, bool Failure>
__attribute__((always_inline)) inline void density_gradient_particle(const DiffusionArgs& g,
                                                                     const PairKernel<K>& kernel, std::size_t i) {
  const double* x = g.x;
  const double* rho = g.rho;
  const double* volume = g.volume;
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2], rhoi = rho[i];
  const BondRule<Failure> bond(g.failure, i);
  DecodedList list(*g.nl, i);
  const std::uint32_t* const nb = list.indices;
  const std::ptrdiff_t count = list.count;
  double s0 = 0, s1 = 0, s2 = 0;
#pragma omp simd reduction(+ : s0, s1, s2)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const std::size_t j = nb[k];
    const double x0 = xi0 - x[3 * j], x1 = xi1 - x[3 * j + 1], x2 = xi2 - x[3 * j + 2];
    // V_j (rho_j - rho_i) grad_i W_ij, grad_i W_ij = F x_ij; F = 0 in the Verlet skin
    const double f =
        kernel.factor(x0 * x0 + x1 * x1 + x2 * x2) * volume[j] * (rho[j] - rhoi) * bond.factor(j, x0, x1, x2);
    s0 += f * x0, s1 += f * x1, s2 += f * x2;
  }
  double* out = g.out + 3 * i;
  if (g.correction) {
    // g_i = C_i s (eq. 4b), C symmetric, stored xx yy zz xy yz xz
    const double* c = g.correction + 6 * i;
    out[0] = c[0] * s0 + c[3] * s1 + c[5] * s2;
    out[1] = c[3] * s0 + c[1] * s1 + c[4] * s2;
    out[2] = c[5] * s0 + c[4] * s1 + c[2] * s2;
  } else {
    out[0] = s0, out[1] = s1, out[2] = s2;
  }
}

// D_i of eq. 4a, added to out[i].
template <KernelKind K, bool Failure>
__attribute__((always_inline)) inline void density_diffusion_particle(const DiffusionArgs& g,
                                                                      const PairKernel<K>& kernel, std::size_t i) {
  const double* x = g.x;
  const double* rho = g.rho;
  const double* volume = g.volume;
  const double* gr = g.gradient;
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2], rhoi = rho[i];
  const double gi0 = gr[3 * i], gi1 = gr[3 * i + 1], gi2 = gr[3 * i + 2];
  const BondRule<Failure> bond(g.failure, i);
  DecodedList list(*g.nl, i);
  const std::uint32_t* const nb = list.indices;
  const std::ptrdiff_t count = list.count;
  double sum = 0;
#pragma omp simd reduction(+ : sum)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const std::size_t j = nb[k];
    const double x0 = xi0 - x[3 * j], x1 = xi1 - x[3 * j + 1], x2 = xi2 - x[3 * j + 2];
    // psi_ij . grad_i W_ij = -F (2 (rho_j - rho_i) + (g_i + g_j) . x_ij)   (eq. 4a)
    const double linear_part = (gi0 + gr[3 * j]) * x0 + (gi1 + gr[3 * j + 1]) * x1 + (gi2 + gr[3 * j + 2]) * x2;
    const double f = kernel.factor(x0 * x0 + x1 * x1 + x2 * x2) * volume[j] * bond.factor(j, x0, x1, x2);
    sum -= f * (2.0 * (rho[j] - rhoi) + linear_part);
  }
  g.out[i] += g.coefficient * sum;
}

// One of the two passes over all particles, in the instance of the kernel and of the bond rule.
template <bool Gradient, KernelKind K, bool Failure>
void run_instance(const DiffusionArgs& g, double h) {
  const PairKernel<K> kernel(h);
  for_each_particle(g.n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
    if constexpr (Gradient) density_gradient_particle<K, Failure>(g, kernel, i);
    else density_diffusion_particle<K, Failure>(g, kernel, i);
  });
}

template <bool Gradient>
void run(KernelKind kernel, const DiffusionArgs& g, double h) {
  const bool failure = g.failure.failed != nullptr;
  if (kernel == KernelKind::WendlandC2) {
    if (failure) run_instance<Gradient, KernelKind::WendlandC2, true>(g, h);
    else run_instance<Gradient, KernelKind::WendlandC2, false>(g, h);
  } else {
    if (failure) run_instance<Gradient, KernelKind::CubicSpline, true>(g, h);
    else run_instance<Gradient, KernelKind::CubicSpline, false>(g, h);
  }
}

}  // namespace

void density_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* rho,
                      const double* volume, const double* correction, double* gradient, std::size_t n,
                      const BondFailure& failure) {
  const DiffusionArgs g{&nl, x, rho, volume, correction, nullptr, gradient, n, 0.0, failure};
  run</*Gradient=*/true>(kernel, g, h);
}

void add_density_diffusion(const NeighbourList& nl, KernelKind kernel, double h, double delta, double wave_speed,
                           const double* x, const double* rho, const double* volume, const double* gradient,
                           double* density_rate, std::size_t n, const BondFailure& failure) {
  const DiffusionArgs g{&nl, x, rho, volume, nullptr, gradient, density_rate, n, delta * h * wave_speed, failure};
  run</*Gradient=*/false>(kernel, g, h);
}

}  // namespace sphforge
