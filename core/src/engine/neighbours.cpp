#include "engine/neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sphforge {

std::size_t NeighbourList::bytes() const {
  return offsets_.capacity() * sizeof(std::size_t) + indices_.capacity() * sizeof(std::uint32_t) +
         (cell_of_.capacity() + cell_start_.capacity() + sorted_.capacity() + neighbour_count_.capacity()) *
             sizeof(std::uint32_t);
}

bool NeighbourList::update(const double* x, std::size_t n, double radius, double skin) {
  bool rebuild = skin <= 0.0 || n != count() || radius + skin != radius_at_build_;
  if (!rebuild) {
    const double limit2 = 0.25 * skin * skin;
    int moved = 0;
#pragma omp parallel for reduction(max : moved) schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double dx = x[3 * i] - x_at_build_[3 * i], dy = x[3 * i + 1] - x_at_build_[3 * i + 1],
                   dz = x[3 * i + 2] - x_at_build_[3 * i + 2];
      // NaN compares false here; the stability check, not the neighbour search, reports it.
      if (dx * dx + dy * dy + dz * dz > limit2) moved = 1;
    }
    rebuild = moved != 0;
  }
  if (!rebuild) return false;
  build(x, n, radius + skin);
  x_at_build_.assign(x, x + 3 * n);
  radius_at_build_ = radius + skin;
  ++builds_;
  return true;
}

void NeighbourList::build(const double* x, std::size_t n, double radius) {
  offsets_.assign(n + 1, 0);
  if (n == 0) return;
  if (n > std::numeric_limits<std::uint32_t>::max()) throw std::length_error("too many particles");

  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = std::numeric_limits<double>::infinity();
    hi[d] = -lo[d];
  }
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], x[3 * i + d]);
      hi[d] = std::max(hi[d], x[3 * i + d]);
    }
  // A cell grid over the bounding box; cells of edge `radius` so that all neighbours of a
  // particle lie in the 27 cells around it. Very elongated clouds (long extrudates) are capped
  // to keep the cell array small: a cell edge larger than the radius stays correct.
  std::int64_t dims[3];
  double edge[3];
  // Never more cells than a few per particle: a cloud blown apart would otherwise fill a huge,
  // nearly empty grid at every rebuild.
  const std::int64_t kMaxCells = std::clamp<std::int64_t>(8 * static_cast<std::int64_t>(n), 4096, std::int64_t(1) << 26);
  double scale = 1.0;
  for (;;) {
    std::int64_t total = 1;
    for (int d = 0; d < 3; ++d) {
      edge[d] = radius * scale;
      dims[d] = std::max<std::int64_t>(1, static_cast<std::int64_t>((hi[d] - lo[d]) / edge[d]) + 1);
      total *= dims[d];
    }
    if (total <= kMaxCells) break;
    scale *= 1.5;
  }
  const std::size_t ncells = static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);

  cell_of_.resize(n);
  cell_start_.assign(ncells + 1, 0);
  sorted_.resize(n);
  auto cell_coord = [&](double v, int d) {
    return std::min<std::int64_t>(dims[d] - 1, static_cast<std::int64_t>((v - lo[d]) / edge[d]));
  };
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t cx = cell_coord(x[3 * i], 0), cy = cell_coord(x[3 * i + 1], 1),
                       cz = cell_coord(x[3 * i + 2], 2);
    cell_of_[i] = static_cast<std::uint32_t>((cz * dims[1] + cy) * dims[0] + cx);
  }
  // Counting sort of particles by cell (stable: ascending index within a cell).
  for (std::size_t i = 0; i < n; ++i) ++cell_start_[cell_of_[i] + 1];
  for (std::size_t c = 0; c < ncells; ++c) cell_start_[c + 1] += cell_start_[c];
  {
    std::vector<std::uint32_t>& fill = neighbour_count_;  // reused as a cursor array here
    fill.assign(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted_[fill[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  }

  const double r2 = radius * radius;
  // Visits the neighbours of i in a fixed order (cells by z, y, x; particles by index).
  auto for_each_neighbour = [&](std::size_t i, auto&& visit) {
    const std::uint32_t c = cell_of_[i];
    const std::int64_t cx = c % dims[0], cy = (c / dims[0]) % dims[1], cz = c / (dims[0] * dims[1]);
    const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
    for (std::int64_t z = std::max<std::int64_t>(0, cz - 1); z <= std::min(dims[2] - 1, cz + 1); ++z)
      for (std::int64_t y = std::max<std::int64_t>(0, cy - 1); y <= std::min(dims[1] - 1, cy + 1); ++y)
        for (std::int64_t xx = std::max<std::int64_t>(0, cx - 1); xx <= std::min(dims[0] - 1, cx + 1); ++xx) {
          const std::size_t cell = static_cast<std::size_t>((z * dims[1] + y) * dims[0] + xx);
          for (std::uint32_t s = cell_start_[cell]; s < cell_start_[cell + 1]; ++s) {
            const std::uint32_t j = sorted_[s];
            if (j == i) continue;
            const double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
            if (dx * dx + dy * dy + dz * dz < r2) visit(j);
          }
        }
  };

  neighbour_count_.resize(n);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t k = 0;
    for_each_neighbour(i, [&](std::uint32_t) { ++k; });
    neighbour_count_[i] = k;
  }
  for (std::size_t i = 0; i < n; ++i) offsets_[i + 1] = offsets_[i] + neighbour_count_[i];
  indices_.resize(offsets_[n]);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t* out = indices_.data() + offsets_[i];
    for_each_neighbour(i, [&](std::uint32_t j) { *out++ = j; });
  }
}

}  // namespace sphforge
