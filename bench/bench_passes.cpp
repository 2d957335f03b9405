// Cost of the per-step neighbour passes on a 3D block of particles on a jittered cubic lattice
// (h = 1.3 dx, cubic spline, a stressed state so that every branch is taken). Each benchmark
// reports items_per_second = particles processed per second by that pass alone, so the passes'
// shares of a step can be compared in one run: `sphforge_bench_passes --benchmark_repetitions=5`.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/heat_conduction.hpp"
#include "engine/neighbours.hpp"
#include "engine/second_order_gradient.hpp"
#include "engine/sph_operators.hpp"
#include "sphforge/fields.hpp"
#include "sphforge/parameters.hpp"
#include "sphforge/plugin_loader.hpp"

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
    corrected_stress(p.data(), S.data(), correction.data(), true, stress_c.data(), n);
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
  std::vector<std::uint64_t> tension((b.n + 63) / 64);
  for (auto _ : state) {
    mark_tension(b.R.data(), b.n, tension.data());  // part of the pass (the step runs it before)
    momentum_rate(b.nl, KernelKind::CubicSpline, b.h, ArtificialViscosity{}, 50.0, b.x.data(), b.v.data(),
                  b.m.data(), b.rho.data(), b.volume.data(), b.stress_c.data(), as, b.R.data(), tension.data(),
                  b.a.data(), b.n);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

// The same pass where no particle is under principal tension (R = 0 everywhere, as in a billet
// under compression): the loop then runs without the artificial-stress terms (they are exact zeros).
void BM_MomentumWithArtificialStressNoTension(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  ArtificialStress as;
  as.w_dx = kernel_value(KernelKind::CubicSpline, b.dx, b.h);
  const std::vector<double> no_tension(b.R.size(), 0.0);
  std::vector<std::uint64_t> tension((b.n + 63) / 64);
  for (auto _ : state) {
    mark_tension(no_tension.data(), b.n, tension.data());
    momentum_rate(b.nl, KernelKind::CubicSpline, b.h, ArtificialViscosity{}, 50.0, b.x.data(), b.v.data(),
                  b.m.data(), b.rho.data(), b.volume.data(), b.stress_c.data(), as, no_tension.data(), tension.data(),
                  b.a.data(), b.n);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

// Heat conduction (eqs. 20-21) and the free-surface area of convection (eq. 22) on the same block:
// a temperature gradient along x and two conductivities in a checkerboard of slabs, so that the
// harmonic mean sees unequal pairs.
void BM_HeatConduction(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  std::vector<double> T(b.n), k(b.n), heat(b.n, 0.0);
  for (std::size_t i = 0; i < b.n; ++i) {
    T[i] = 300.0 + 1e4 * b.x[3 * i];
    k[i] = (static_cast<int>(b.x[3 * i + 2] / (4 * b.dx)) % 2) ? 150.0 : 20.0;
  }
  for (auto _ : state)
    heat_conduction(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.volume.data(), T.data(), k.data(), heat.data(),
                    b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

void BM_SurfaceArea(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  std::vector<double> area(b.n);
  for (auto _ : state) surface_area(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.volume.data(), area.data(), b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

// The same two pair passes with the bond-failure rule (docs/theory.md eqs. 112-114) active: every
// other particle failed, so about a quarter of the pairs are broken bonds and the rule is decided on
// every pair. Compare with the two benchmarks above: the price a scene with a failure criterion pays
// (a scene without one runs exactly the loops above).
struct FailureState {
  std::vector<double> failed, sigma;
  explicit FailureState(const Block& b) : failed(b.n, 0.0), sigma(6 * b.n) {
    for (std::size_t i = 0; i < b.n; i += 2) failed[i] = 1.0;
    cauchy_stress(b.p.data(), b.S.data(), sigma.data(), b.n);
  }
  BondFailure rule() const { return {failed.data(), sigma.data()}; }
};

void BM_VelocityGradientCorrectedWithFailure(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  const FailureState f(b);
  for (auto _ : state)
    velocity_gradient(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.v.data(), b.volume.data(), true, b.L.data(),
                      nullptr, b.correction.data(), b.n, f.rule());
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

void BM_MomentumWithArtificialStressWithFailure(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  const FailureState f(b);
  ArtificialStress as;
  as.w_dx = kernel_value(KernelKind::CubicSpline, b.dx, b.h);
  std::vector<std::uint64_t> tension((b.n + 63) / 64);
  for (auto _ : state) {
    mark_tension(b.R.data(), b.n, tension.data());
    momentum_rate(b.nl, KernelKind::CubicSpline, b.h, ArtificialViscosity{}, 50.0, b.x.data(), b.v.data(),
                  b.m.data(), b.rho.data(), b.volume.data(), b.stress_c.data(), as, b.R.data(), tension.data(),
                  b.a.data(), b.n, f.rule());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

// The second-order gradient correction (docs/theory.md section 18, numerics.gradient_correction_order
// = "second"): its three pair passes, to compare with the first-order gradient and momentum above.
// A step with it runs the first-order momentum pass too (eq. 136 adds to it), and these three instead
// of BM_VelocityGradientCorrected.
struct SecondOrderState {
  std::vector<double> B, C, stress_b;
  explicit SecondOrderState(Block& b) : B(27 * b.n), C(6 * b.n), stress_b(27 * b.n) {
    second_order_correction(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.volume.data(), B.data(), C.data(),
                            nullptr, b.n);
    second_order_stress(b.p.data(), b.S.data(), B.data(), stress_b.data(), b.n);
  }
};

SecondOrderState& second_order_state(Block& b) {
  static SecondOrderState s(b);
  return s;
}

void BM_SecondOrderCorrection(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  SecondOrderState& s = second_order_state(b);
  for (auto _ : state)
    second_order_correction(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.volume.data(), s.B.data(), s.C.data(),
                            nullptr, b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

void BM_SecondOrderVelocityGradient(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  SecondOrderState& s = second_order_state(b);
  for (auto _ : state)
    second_order_velocity_gradient(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.v.data(), b.volume.data(),
                                   s.B.data(), s.C.data(), b.L.data(), b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

void BM_SecondOrderMomentumTerm(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  SecondOrderState& s = second_order_state(b);
  for (auto _ : state)
    second_order_momentum_term(b.nl, KernelKind::CubicSpline, b.h, b.x.data(), b.m.data(), b.volume.data(),
                               s.stress_b.data(), b.a.data(), b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

void BM_JaumannRotation(benchmark::State& state) {
  Block& b = block(static_cast<int>(state.range(0)));
  for (auto _ : state) jaumann_rotation(b.L.data(), 1e-9, b.S.data(), b.n);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.n));
}

// Material passes (plugins, docs/theory.md eqs. 15-17, 33-37) on the block's particles: every
// particle flows plastically in every call (a deviatoric strain increment of 0.002 per step, far
// above the yield strain), so each call does the full return mapping. Compare per particle with
// BM_JaumannRotation (the stress-rate pass) and with the whole step (sphforge_bench_step).
struct MaterialBlock {
  std::unique_ptr<Material> material;
  FieldRegistry fields;
  std::vector<double> L, S, p, rho, T, heat;
  std::size_t n;
  MaterialBlock(PluginLoader& loader, const std::string& plugin, const json& params, std::size_t count, bool thermal)
      : n(count) {
    const LoadedPlugin& lp = loader.load(PluginKind::Material, plugin);
    material = lp.descriptor->make_material(validate_parameters(params, lp.descriptor->parameters, "bench", "/material"));
    for (const FieldInfo& f : material->fields()) fields.declare(f, "bench");
    fields.allocate(n);
    L.assign(9 * n, 0.0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.5, 1.5);
    // Isochoric stretching along x at about 2 1/s (x 1e-3 s = 0.002 per step), varied per particle.
    for (std::size_t i = 0; i < n; ++i) {
      const double r = 2.0 * u(rng);
      L[9 * i] = r;
      L[9 * i + 4] = L[9 * i + 8] = -0.5 * r;
      L[9 * i + 1] = 0.3 * r;
    }
    S.assign(6 * n, 0.0);
    p.assign(n, 0.0);
    rho.assign(n, material->reference_density());
    T.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) T[i] = 300.0 + 200.0 * u(rng);
    heat.assign(n, 0.0);
    if (!thermal) T.clear();
  }
  void step() {
    MaterialBatch b;
    b.count = n;
    b.dt = 1e-3;
    b.velocity_gradient = L.data();
    b.density = rho.data();
    b.deviatoric_stress = S.data();
    b.pressure = p.data();
    b.fields = &fields;
    if (!T.empty()) {
      b.temperature = T.data();
      b.heat_source = heat.data();
    }
    material->update_stress(b);
  }
};

PluginLoader& plugin_loader() {
  static PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  return loader;
}

void run_material(benchmark::State& state, MaterialBlock& m) {
  for (int k = 0; k < 5; ++k) m.step();  // into plastic flow
  for (auto _ : state) m.step();
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(m.n));
  state.counters["failed_returns"] = static_cast<double>(m.material->failed_returns());
}

std::size_t block_count(int side) { return static_cast<std::size_t>(side) * side * side; }

// Copper of the Taylor bar: linear hardening (one Newton correction).
void BM_MaterialElastoplastic(benchmark::State& state) {
  static MaterialBlock m(plugin_loader(), "elastoplastic",
                         {{"density", 8930}, {"youngs_modulus", 117e9}, {"poisson_ratio", 0.35},
                          {"yield_stress", 400e6}, {"hardening_modulus", 100e6}},
                         block_count(static_cast<int>(state.range(0))), false);
  run_material(state, m);
}

// AA7075-T6 (friction_extrusion.md): B = 0, rate and temperature terms, thermal.
void BM_MaterialJohnsonCookAA7075(benchmark::State& state) {
  static MaterialBlock m(plugin_loader(), "johnson_cook",
                         {{"density", 2810}, {"youngs_modulus", 71.7e9}, {"poisson_ratio", 0.33}, {"A", 546e6},
                          {"C", 0.024}, {"m", 1.57}, {"reference_strain_rate", 1.0}, {"reference_temperature", 295.15},
                          {"melting_temperature", 750.15}, {"specific_heat", 795.8}, {"conductivity", 166.1}},
                         block_count(static_cast<int>(state.range(0))), true);
  run_material(state, m);
}

// Brass (friction_stir_back_extrusion.md): strain hardening, rate and temperature terms, thermal.
void BM_MaterialJohnsonCookBrass(benchmark::State& state) {
  static MaterialBlock m(plugin_loader(), "johnson_cook",
                         {{"density", 8500}, {"youngs_modulus", 100e9}, {"poisson_ratio", 0.34}, {"A", 112e6},
                          {"B", 505e6}, {"n", 0.42}, {"C", 0.009}, {"m", 1.68}, {"reference_strain_rate", 1.0},
                          {"reference_temperature", 298.15}, {"melting_temperature", 1189.15},
                          {"specific_heat", 380}, {"conductivity", 120}},
                         block_count(static_cast<int>(state.range(0))), true);
  run_material(state, m);
}

// HX220 steel (friction_drilling.md): strain hardening, rate independent (C = 0), thermal.
void BM_MaterialJohnsonCookHX220(benchmark::State& state) {
  static MaterialBlock m(plugin_loader(), "johnson_cook",
                         {{"density", 7850}, {"youngs_modulus", 210e9}, {"poisson_ratio", 0.3}, {"A", 212.2e6},
                          {"B", 409.2e6}, {"n", 0.3524}, {"C", 0.0}, {"m", 0.7521}, {"reference_strain_rate", 0.01},
                          {"reference_temperature", 293.15}, {"melting_temperature", 1773.15},
                          {"specific_heat", 500}, {"conductivity", 50}},
                         block_count(static_cast<int>(state.range(0))), true);
  run_material(state, m);
}

// 46^3 = 97,336 particles: the size of the SPH-core throughput target (about 1e5).
BENCHMARK(BM_NeighbourBuild)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_VelocityGradientCorrected)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MomentumWithArtificialStress)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_VelocityGradientCorrectedWithFailure)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MomentumWithArtificialStressWithFailure)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SecondOrderCorrection)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SecondOrderVelocityGradient)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SecondOrderMomentumTerm)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MomentumWithArtificialStressNoTension)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_HeatConduction)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SurfaceArea)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_JaumannRotation)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
BENCHMARK(BM_MaterialElastoplastic)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MaterialJohnsonCookAA7075)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MaterialJohnsonCookBrass)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MaterialJohnsonCookHX220)->Arg(46)->Unit(benchmark::kMillisecond)->UseRealTime();
