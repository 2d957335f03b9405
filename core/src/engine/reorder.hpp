// Locality reordering: particles sorted by the Morton (Z-order) code of their cell, so that
// particles close in space are close in memory and the neighbour passes read x, v, stress of a
// particle's neighbours from a few cache lines instead of from all over the arrays.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sphforge/fields.hpp"
#include "sphforge/process.hpp"

namespace sphforge {

/// 63-bit Morton code of a cell (21 bits per coordinate; larger coordinates are clamped).
std::uint64_t morton_code(std::uint32_t cx, std::uint32_t cy, std::uint32_t cz);

/// The permutation new[i] = old[order[i]] that sorts the particles of each body range by the
/// Morton code of their cell (cubic cells of edge `cell` over the bounding box of all particles),
/// ties by old index. Particles only move within their own range (material plugins act on
/// contiguous ranges); particles outside every range keep their place. Deterministic: it depends
/// on the positions only, not on the number of threads.
void morton_order(const double* x, std::size_t n, double cell, std::span<const BodyRange> ranges,
                  std::vector<std::size_t>& order);

/// Applies morton_order to every registered field (FieldRegistry::permute). Positions must be
/// the `position` field. Returns false (and changes nothing) when the order is already sorted.
/// Everything indexed by particle outside the registry (neighbour lists, per-step scratch) must be
/// rebuilt afterwards.
bool reorder_by_cell(FieldRegistry& fields, std::span<const BodyRange> ranges, double cell);

}  // namespace sphforge
