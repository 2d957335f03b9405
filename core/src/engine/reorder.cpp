#include "engine/reorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace sphforge {

namespace {
// Spreads the low 21 bits of v so that there are two zero bits between consecutive bits.
std::uint64_t spread3(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}
}  // namespace

std::uint64_t morton_code(std::uint32_t cx, std::uint32_t cy, std::uint32_t cz) {
  constexpr std::uint32_t kMax = (1u << 21) - 1;
  return spread3(std::min(cx, kMax)) | spread3(std::min(cy, kMax)) << 1 | spread3(std::min(cz, kMax)) << 2;
}

void morton_order(const double* x, std::size_t n, double cell, std::span<const BodyRange> ranges,
                  std::vector<std::size_t>& order) {
  order.resize(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  if (n == 0 || !(cell > 0.0)) return;
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], x[3 * i + d]);
  if (!(std::isfinite(lo[0]) && std::isfinite(lo[1]) && std::isfinite(lo[2]))) return;  // NaN: leave it
  const double inv = 1.0 / cell;
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed;
  for (const BodyRange& r : ranges) {
    if (r.first >= n || r.count < 2) continue;
    const std::size_t end = std::min(n, r.first + r.count);
    keyed.resize(end - r.first);
#pragma omp parallel for schedule(static)
    for (std::size_t i = r.first; i < end; ++i) {
      std::uint32_t c[3];
      for (int d = 0; d < 3; ++d) {
        const double t = (x[3 * i + d] - lo[d]) * inv;
        // Also maps NaN to 0 (the stability check reports it, not the reordering).
        c[d] = t >= 0.0 ? static_cast<std::uint32_t>(std::min(t, 2097151.0)) : 0u;
      }
      keyed[i - r.first] = {morton_code(c[0], c[1], c[2]), i};
    }
    std::sort(keyed.begin(), keyed.end());  // (key, old index): a strict total order, no ties
    for (std::size_t k = 0; k < keyed.size(); ++k) order[r.first + k] = keyed[k].second;
  }
}

bool reorder_by_cell(FieldRegistry& fields, std::span<const BodyRange> ranges, double cell) {
  std::vector<std::size_t> order;
  morton_order(fields.f64(field::position), fields.size(), cell, ranges, order);
  bool identity = true;
  for (std::size_t i = 0; i < order.size() && identity; ++i) identity = order[i] == i;
  if (identity) return false;
  fields.permute(order);
  return true;
}

}  // namespace sphforge
