// Simulation::memory_breakdown(): everything the engine holds per particle, item by item, so that
// the benchmark (bench/bench_step.cpp) and docs/bench.md ("Memory per particle") can say where
// the bytes per particle go. Capacities, not sizes: what is allocated is what the process holds.
#include <numeric>
#include <utility>

#include "engine/simulation.hpp"

namespace sphforge {

namespace {
template <class T>
std::size_t held(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
}  // namespace

std::vector<Simulation::MemoryItem> Simulation::memory_breakdown() const {
  std::vector<MemoryItem> items;
  // Fields one by one (FieldRegistry::bytes() is their sum; the per-field split comes from the
  // shapes, which is what allocate() sized them to).
  std::size_t shaped = 0;
  for (const std::string& name : fields_.names()) {
    if (!fields_.allocated(name)) continue;
    const std::size_t b = fields_.size() * static_cast<std::size_t>(fields_.info(name).components) * 8u;
    items.push_back({"field " + name, b});
    shaped += b;
  }
  // Any spare capacity (a resize that grew the arrays) as one item, so that the total is exact.
  if (fields_.bytes() > shaped) items.push_back({"field capacity beyond size", fields_.bytes() - shaped});
  using Named = std::pair<const NeighbourList*, const char*>;
  for (const auto& [nl, prefix] : {Named{&neighbours_, "neighbours"}, Named{&thermal_neighbours_, "thermal neighbours"}}) {
    items.push_back({std::string(prefix) + " list entries", nl->list_bytes()});
    items.push_back({std::string(prefix) + " list index", nl->index_bytes()});
    items.push_back({std::string(prefix) + " build scratch", nl->build_scratch_bytes()});
    items.push_back({std::string(prefix) + " positions at build", nl->watch_bytes()});
  }
  items.push_back({"contact scratch", contact_.bytes() - contact_.history_bytes()});
  items.push_back({"friction memory (touching particles only)", contact_.history_bytes()});
  items.push_back({"pass scratch (volume, correction or artificial stress; sigma C with symmetry)", held(scratch_)});
  items.push_back({"tension bits (artificial stress)", held(tension_bits_)});
  items.push_back({"yield stress scratch", held(yield_scratch_)});
  items.push_back({"bond failure scratch", held(bond_stress_) + held(ext_failed_)});
  items.push_back({"physical density scratch (mass scaling)", held(physical_density_)});
  items.push_back({"constraint scratch", held(constrained_scratch_)});
  items.push_back({"xsph scratch", held(xsph_scratch_)});
  items.push_back({"density diffusion scratch (g, rate)", held(density_gradient_) + held(diffusion_rate_)});
  items.push_back({"symmetry extended arrays", held(ext_x_) + held(ext_v_) + held(ext_m_) + held(ext_rho_) +
                                                   held(ext_T_) + held(ext_thermal_x_)});
  std::size_t ghosts = 0;
  for (const Symmetry* s : {&symmetry_, &thermal_symmetry_})
    ghosts += held(s->sources()) + held(s->image_of_ghost()) + held(s->images());
  items.push_back({"symmetry ghost index", ghosts});
  items.push_back({"thermal scratch", held(conductivity_) + held(specific_heat_) + held(heat_W_) + held(area_) +
                                          held(thermal_volume_)});
  return items;
}

std::size_t Simulation::memory_bytes() const {
  const auto items = memory_breakdown();
  return std::accumulate(items.begin(), items.end(), std::size_t{0},
                         [](std::size_t s, const MemoryItem& m) { return s + m.bytes; });
}

}  // namespace sphforge
