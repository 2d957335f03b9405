// Cost of evaluating the SPH smoothing kernels (sphforge/kernels.hpp) over a batch of pair
// distances, as a pair loop does: W and the gradient factor (dW/dr)/r per pair.
// items_per_second in the output is kernel evaluations (pairs) per second.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <vector>

#include "sphforge/kernels.hpp"

namespace {

// Distances spread evenly over [0, 2.2h) in a shuffled order (7919 is coprime with the power-of-two
// sizes), so ~91% lie inside the support and the q < 1 / q >= 1 branch is not predictable. A real
// cell-list loop rejects more candidates by distance first; what is timed here is the kernel maths.
std::vector<double> pair_distances(std::size_t n, double h) {
  std::vector<double> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = 2.2 * h * static_cast<double>((i * 7919) % n) / static_cast<double>(n);
  return r;
}

template <sphforge::KernelKind Kind>
void BM_Kernel(benchmark::State& state) {
  const double h = 1.3e-3;
  const auto r = pair_distances(static_cast<std::size_t>(state.range(0)), h);
  for (auto _ : state) {
    double sum_w = 0.0, sum_f = 0.0;
    for (double ri : r) {
      sum_w += sphforge::kernel_value(Kind, ri, h);
      sum_f += sphforge::kernel_gradient_factor(Kind, ri, h);
    }
    benchmark::DoNotOptimize(sum_w);
    benchmark::DoNotOptimize(sum_f);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

BENCHMARK_TEMPLATE(BM_Kernel, sphforge::KernelKind::CubicSpline)->Arg(1 << 12)->Arg(1 << 16);
BENCHMARK_TEMPLATE(BM_Kernel, sphforge::KernelKind::WendlandC2)->Arg(1 << 12)->Arg(1 << 16);

}  // namespace
