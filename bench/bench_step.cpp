// Whole-step throughput of the real engine: the bundled ram-extrusion case (elastoplastic billet,
// coulomb friction, prescribed ram speed) scaled to about 1e5 particles, run through
// Simulation::run for a fixed number of steps with every output pushed past the end. Reports
// particle-steps/s over the step loop alone (the wall time summary.json reports: the scene build
// and the first and last frames are outside it) and the memory held per particle (fields,
// neighbour lists, scratch).
//
//   build/release/bin/sphforge_bench_step --benchmark_repetitions=3
//
// The ram is driven at 0.08 m/s so that the particles near it move about as far per step as the
// fastest particles of the quick case do in steady extrusion: the Verlet lists are then rebuilt
// every ~20 steps, as in a real run (the counter `steps_per_neighbour_build` shows it). At the
// quick case's 1 mm/s the lists would never be rebuilt within the benchmark.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "engine/simulation.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/plugin_loader.hpp"

namespace {

using namespace sphforge;
namespace fs = std::filesystem;

void BM_WholeStep(benchmark::State& state) {
  const long long steps = state.range(0);
  const fs::path dir = fs::temp_directory_path() / ("sphforge_bench_step_" + std::to_string(::getpid()));
  const std::string case_file = std::string(SPHFORGE_SOURCE_DIR) + "/cases/ram_extrusion/paste_orifice_quick.json";
  // 15 mm barrel, 15 mm billet, 0.3 mm spacing: 94,550 particles.
  const std::vector<std::string> overrides = {
      "process.barrel_diameter=15 mm", "process.ram_diameter=14.93 mm", "process.billet_height=15 mm",
      "process.particle_spacing=0.3 mm", "controllers.0.value=0.08 m/s",
      "run.end_time=100 s",              "run.output_interval=100 s",   "run.history_interval=100 s",
      "run.max_steps=" + std::to_string(steps)};
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  double particles = 0.0, bytes = 0.0, builds = 0.0;
  for (auto _ : state) {
    fs::remove_all(dir);
    Simulation sim(load_case(case_file, overrides), loader);
    const auto result = sim.run(dir, ProgressMode::Quiet);
    if (result.exit_code != 0) {
      state.SkipWithError(("run failed: " + result.message).c_str());
      break;
    }
    std::ifstream in(dir / "summary.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    state.SetIterationTime(summary.at("wall_time_s").get<double>());
    particles = static_cast<double>(sim.particle_count());
    bytes = static_cast<double>(sim.memory_bytes());
    builds = static_cast<double>(sim.neighbour_builds());
  }
  fs::remove_all(dir);
  state.SetItemsProcessed(state.iterations() * steps * static_cast<int64_t>(particles));
  state.counters["particles"] = particles;
  state.counters["bytes_per_particle"] = particles > 0 ? bytes / particles : 0.0;
  state.counters["steps_per_neighbour_build"] = builds > 0 ? double(steps) / builds : 0.0;
}

// items_per_second = particle-steps per second of the whole step loop.
BENCHMARK(BM_WholeStep)->Arg(100)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);

}  // namespace
