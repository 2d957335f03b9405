#include "engine/tool_heat.hpp"

#include "engine/pair_kernel.hpp"

#include <cmath>
#include <limits>

namespace sphforge {

void deposit_tool_heat(const std::vector<ToolHeatRecord>& records, const NeighbourList& nl, KernelKind kernel,
                       double h, const double* x, const double* mass, double mass_scaling,
                       const std::int64_t* body, const std::vector<BodyRange>& bodies, double* heat_source,
                       std::size_t n, const std::uint32_t* ghost_source, const double* h_point) {
  // With variable spacing (h_point) each pair's kernel has h_ij (eq. 138); its support is within
  // that of the largest h, which the lists were built for.
  auto pair_h = [&](std::size_t i, std::size_t j) {
    return h_point ? pair_smoothing_length(h_point[i], h_point[j]) : h;
  };
  // The real particle behind a list entry (a ghost's source, eq. 31).
  auto real = [&](std::size_t j) -> std::size_t { return ghost_source && j >= n ? ghost_source[j - n] : j; };
  // Sequential over the contacts (a small fraction of the particles): a contact scatters into
  // several tool particles and neighbouring contacts share them, and the fixed order keeps the
  // sums bit for bit independent of the thread count.
  for (const ToolHeatRecord& rec : records) {
    const std::size_t i = rec.particle;
    const long long tool = static_cast<long long>(rec.tool);
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    auto r2_to = [&](std::size_t j) {
      const double d0 = xi[0] - x[3 * j], d1 = xi[1] - x[3 * j + 1], d2 = xi[2] - x[3 * j + 2];
      return d0 * d0 + d1 * d1 + d2 * d2;
    };
    // Kernel weights of the tool's particles within the support of i (eq. 91).
    double wsum = 0.0;
    nl.for_each(i, [&](std::size_t j) {
      if (bodies[static_cast<std::size_t>(body[real(j)])].attached_tool != tool) return;
      const double r2 = r2_to(j), hij = pair_h(i, j), support = kernel_support_radius(hij);
      if (r2 < support * support) wsum += kernel_value(kernel, std::sqrt(r2), hij);
    });
    if (wsum > 0.0) {
      const double scale = rec.heat_W / wsum;
      nl.for_each(i, [&](std::size_t j) {
        const std::size_t r = real(j);
        if (bodies[static_cast<std::size_t>(body[r])].attached_tool != tool) return;
        const double r2 = r2_to(j), hij = pair_h(i, j), support = kernel_support_radius(hij);
        if (r2 < support * support)
          heat_source[r] += scale * kernel_value(kernel, std::sqrt(r2), hij) * mass_scaling / mass[r];
      });
      continue;
    }
    // No tool particle within the support (a tool body thinner than the surface it carries, or
    // placed away from it): the nearest one takes all, so that the heat is never lost.
    double best = std::numeric_limits<double>::infinity();
    std::size_t nearest = 0;
    bool found = false;
    for (const BodyRange& b : bodies) {
      if (b.attached_tool != tool) continue;
      for (std::size_t j = b.first; j < b.first + b.count; ++j) {
        const double r2 = r2_to(j);
        if (r2 < best) {
          best = r2;
          nearest = j;
          found = true;
        }
      }
    }
    if (found) heat_source[nearest] += rec.heat_W * mass_scaling / mass[nearest];
  }
}

}  // namespace sphforge
