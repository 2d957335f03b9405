// The tools' share of the friction heat into their attached thermal particles (docs/theory.md
// eq. 91, docs/contact.md "Heat into the tools").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/contact.hpp"
#include "engine/neighbours.hpp"
#include "sphforge/kernels.hpp"
#include "sphforge/process.hpp"

namespace sphforge {

/// Spreads each record's heat Q (W, the tool's share (1 - phi) |f_t| |v_t| of one contact) over
/// the particles of that tool's attached bodies within the kernel support of the contact particle
/// i, in proportion to W(|x_i - x_j|, h) (eq. 91); when none lies within the support, the nearest
/// particle of the tool's bodies takes all of Q. The weights are normalised, so the heat added is
/// Q to round-off. `nl`: lists over all particles (the thermal lists). Adds Q_j / m_j (physical mass
/// m / mass_scaling) to heat_source (W/kg).
/// With symmetry the lists also hold ghosts j >= n (positions in x, which is then the extended
/// array): `ghost_source[j - n]` is the real particle a ghost images, and it receives the ghost's
/// share (its image contact heats the source the same way). ghost_source null: no ghosts.
void deposit_tool_heat(const std::vector<ToolHeatRecord>& records, const NeighbourList& nl, KernelKind kernel,
                       double h, const double* x, const double* mass, double mass_scaling,
                       const std::int64_t* body, const std::vector<BodyRange>& bodies, double* heat_source,
                       std::size_t n, const std::uint32_t* ghost_source, const double* h_point = nullptr);

}  // namespace sphforge
