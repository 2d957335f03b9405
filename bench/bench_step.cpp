// Whole-step throughput of the real engine: the bundled ram-extrusion case (elastoplastic billet,
// coulomb friction, prescribed ram speed) scaled to about 1e5 particles, run through
// Simulation::run for a fixed number of steps with every output pushed past the end. Reports
// particle-steps/s over the step loop alone (the wall time summary.json reports: the scene build
// and the first and last frames are outside it) and the memory held per particle (fields,
// neighbour lists, scratch; the item-by-item breakdown of Simulation::memory_breakdown() goes to
// stderr, docs/bench.md "Memory per particle"), with the process's peak resident growth to compare.
//
//   build/release/bin/sphforge_bench_step --benchmark_repetitions=3
//
// The ram is driven at 0.02 m/s so that the Verlet lists are rebuilt about every 15 steps, as in
// the quick case over its whole run (3,889 steps, 261 builds); the counter
// `steps_per_neighbour_build` shows it. At the quick case's 1 mm/s the lists would hardly be
// rebuilt within the benchmark.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/simulation.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/plugin_loader.hpp"

namespace {

using namespace sphforge;
namespace fs = std::filesystem;

// A kB figure of /proc/self/status ("VmRSS:", "VmHWM:"), in bytes; 0 when unavailable.
double proc_status_bytes(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return 1024.0 * std::stod(line.substr(key.size()));
  return 0.0;
}

// Resets the peak resident set size (VmHWM) to the current one (Linux >= 4.0); false if refused.
bool reset_peak_rss() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

void BM_WholeStep(benchmark::State& state) {
  const long long steps = state.range(0);
  const bool density_diffusion = state.range(1) != 0;
  const fs::path dir = fs::temp_directory_path() / ("sphforge_bench_step_" + std::to_string(::getpid()));
  const std::string case_file = std::string(SPHFORGE_SOURCE_DIR) + "/cases/ram_extrusion/paste_orifice_quick.json";
  // 15 mm barrel, 15 mm billet, 0.3 mm spacing: 94,550 particles.
  const std::vector<std::string> overrides = {
      "process.barrel_diameter=15 mm", "process.ram_diameter=14.93 mm", "process.billet_height=15 mm",
      "process.particle_spacing=0.3 mm", "controllers.0.value=0.02 m/s",
      "run.end_time=100 s",              "run.output_interval=100 s",   "run.history_interval=100 s",
      "run.max_steps=" + std::to_string(steps)};
  // The optional delta-SPH term (theory eq. 4a) at its usual delta, for its cost in the same run.
  std::vector<std::string> case_overrides = overrides;
  if (density_diffusion) case_overrides.push_back("numerics.density_diffusion=0.1");
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  double particles = 0.0, bytes = 0.0, field_bytes = 0.0, list_bytes = 0.0, pairs = 0.0, builds = 0.0;
  double rss_growth = -1.0, wide = 0.0;
  std::vector<Simulation::MemoryItem> breakdown;
  for (auto _ : state) {
    fs::remove_all(dir);
    // The process's own growth over the run (peak minus the resident size before the scene is
    // built: libraries, plugins and the allocator's earlier pools are not the particles').
    const double rss_before = proc_status_bytes("VmRSS:");
    const bool peak_reset = reset_peak_rss();
    Simulation sim(load_case(case_file, case_overrides), loader);
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
    field_bytes = static_cast<double>(sim.fields().bytes());
    list_bytes = static_cast<double>(sim.neighbours().bytes());
    pairs = static_cast<double>(sim.neighbours().pairs());
    builds = static_cast<double>(sim.neighbour_builds());
    wide = static_cast<double>(sim.neighbours().wide_rows());
    breakdown = sim.memory_breakdown();
    if (peak_reset) rss_growth = proc_status_bytes("VmHWM:") - rss_before;
  }
  fs::remove_all(dir);
  state.SetItemsProcessed(state.iterations() * steps * static_cast<int64_t>(particles));
  state.counters["particles"] = particles;
  // Memory per particle: all of it, the registered fields, the neighbour lists with their
  // cell-list scratch (the rest is contact and pass scratch), and list entries per particle.
  const double per = particles > 0 ? 1.0 / particles : 0.0;
  state.counters["bytes_per_particle"] = bytes * per;
  state.counters["field_bytes_per_particle"] = field_bytes * per;
  state.counters["list_bytes_per_particle"] = list_bytes * per;
  state.counters["scratch_bytes_per_particle"] = (bytes - field_bytes - list_bytes) * per;
  state.counters["neighbours_per_particle"] = pairs * per;
  // Lists that span more than 65,535 indices and keep 4 bytes per entry (theory.md section 7).
  state.counters["wide_list_fraction"] = wide * per;
  state.counters["steps_per_neighbour_build"] = builds > 0 ? double(steps) / builds : 0.0;
  // What the process really grew by, per particle (peak RSS over the run, scene build included,
  // minus the RSS before it); -1 when the peak could not be reset. Transients that memory_bytes()
  // does not hold (the reordering's gather buffer, the output writers) show up here.
  state.counters["peak_rss_growth_per_particle"] = rss_growth >= 0.0 ? rss_growth * per : -1.0;
  // The breakdown behind bytes_per_particle (docs/bench.md, "Memory per particle"), on stderr.
  std::fprintf(stderr, "memory per particle (%.0f particles):\n", particles);
  for (const auto& item : breakdown)
    if (item.bytes > 0) std::fprintf(stderr, "  %9.1f B  %s\n", double(item.bytes) * per, item.name.c_str());
  std::fprintf(stderr, "  %9.1f B  total (memory_bytes)\n", bytes * per);
}

// items_per_second = particle-steps per second of the whole step loop.
// Second argument: 1 with density diffusion (theory eq. 4a), 0 without.
BENCHMARK(BM_WholeStep)->Args({60, 0})->Args({60, 1})->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);

}  // namespace
