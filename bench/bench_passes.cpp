// Cost of the per-step neighbour passes on a 3D block of particles on a jittered cubic lattice
// (h = 1.3 dx, cubic spline, a stressed state so that every branch is taken). Each benchmark
// reports items_per_second = particles processed per second by that pass alone, so the passes'
// shares of a step can be compared in one run: `sphforge_bench_passes --benchmark_repetitions=5`.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/neighbours.hpp"
#include "engine/sph_operators.hpp"

namespace {

using namespace sphforge;

struct Block {
  std::size_t n = 0;
  double dx = 1e-3, h = 1.3e-3;
  std::vector<double> x, v, m, rho, volume, L, S, p, sigma, R, a, correction, stress_c;
  NeighbourList nl;

  explicit Block(int side) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> jitter(-0.1, 0.1);
    for (int k = 0; k < side; ++k)
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
          const double p3[3] = {i * dx, j * dx, k * dx};
          for (int d = 0; d < 3; ++d) x.push_back(p3[d] + jitter(rng) * dx);
          // A shear-plus-compression velocity field, so the viscosity branch is exercised.
          v.insert(v.end(), {1e-3 * p3[1], -1e-3 * p3[2], -1e-2 * p3[2]});
        }
    n = x.size() / 3;
    m.assign(n, 1000.0 * dx * dx * dx);
    rho.assign(n, 1000.0);
    volume.assign(n, dx * dx * dx);
    L.assign(9 * n, 0.0);
    S.assign(6 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) S[6 * i + 3] = (i % 2 ? 1e5 : -1e5);
    p.assign(n, 1e5);
    for (std::size_t i = 0; i < n; i += 3) p[i] = -2e5;  // some tension for the artificial stress
    sigma.assign(6 * n, 0.0);
    R.assign(6 * n, 0.0);
    a.assign(3 * n, 0.0);
    nl.build(x.data(), n, 2.0 * h + 0.2 * h);
    stress_over_density_squared(p.data(), S.data(), rho.data(), sigma.data(), n);
    artificial_stress(sigma.data(), 0.3, R.data(), n);
    correction.assign(6 * n, 0.0);
    stress_c.assign(9 * n, 0.0);
    velocity_gradient(nl, KernelKind::CubicSpline, h, x.data(), v.data(), volume.data(), true, L.data(), nullptr,
                      correction.data(), n);
    corrected_stress(p.data(), S.data(), correction.data(), stress_c.data(), n);
  }
};

Block& block(int side) {
  static Block b(side);
  return b;
}

void BM_NeighbourBuild(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  for (auto _ : state) b.nl.build(b.x.data(), b.n, 2.0 * b.h + 0.2 * b.h);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
  state.counters["neighbours_per_particle"] = double(b.nl.pairs()) / double(b.n);
  state.counters["list_bytes_per_particle"] = double(b.nl.bytes()) / double(b.n);
}

void BM_VelocityGradientCorrected(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  for (auto _ : state)
    velocity_gradient(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.v.data(), b.volume.data(), true, b.L.data(),
                      nullptr, b.correction.data(), b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

void BM_MomentumWithArtificialStress(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  ArtificialStress as;
  as.w_dx = kernel_value(KernelKind::CubicSpline, b.dx, b.h);
  for (auto _ : state)
    momentum_rate(b.nl, KernelKind::CubicSpline, b.h, ArtificialViscosity{}, 50.0, b.x.data(), b.v.data(),
                  b.m.data(), b.rho.data(), b.volume.data(), b.stress_c.data(), as, b.R.data(), b.a.data(), b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

void BM_JaumannRotation(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  for (auto _ : state) jaumann_rotation(b.L.data(), 1e-9, b.S.data(), b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

// 46^3 = 97,336 particles: the size of the SPH-core throughput target (about 1e5).
BENCHMARK(BM_NeighbourBuild)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_VelocityGradientCorrected)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MomentumWithArtificialStress)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_JaumannRotation)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
