#include "engine/neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sphforge {

std::size_t NeighbourList::pairs() const {
  std::size_t total = 0;
  for (const std::uint32_t p : chunk_pairs_) total += p;
  return total;
}

std::size_t NeighbourList::wide_rows() const {
  std::size_t total = 0;
  for (const std::uint32_t b : base_of_) total += (b & kWide) != 0 ? 1 : 0;
  return total;
}

std::size_t NeighbourList::list_bytes() const {
  std::size_t total = 0;
  for (const auto& c : chunks_) total += c.capacity() * sizeof(std::uint16_t);
  return total;
}

std::size_t NeighbourList::index_bytes() const {
  std::size_t total = (end_.capacity() + base_of_.capacity() + chunk_used_.capacity() + chunk_pairs_.capacity()) *
                          sizeof(std::uint32_t) +
                      chunk_data_.capacity() * sizeof(void*) + chunks_.capacity() * sizeof(chunks_[0]) +
                      candidates_.capacity() * sizeof(candidates_[0]);
  for (const auto& c : candidates_) total += c.capacity() * sizeof(std::uint32_t);
  return total;
}

std::size_t NeighbourList::build_scratch_bytes() const {
  return (cell_of_.capacity() + cell_start_.capacity() + sorted_.capacity()) * sizeof(std::uint32_t) +
         sorted_x_.capacity() * sizeof(float);
}

std::size_t NeighbourList::watch_bytes() const { return x_at_build_.capacity() * sizeof(float); }

std::size_t NeighbourList::bytes() const {
  return list_bytes() + index_bytes() + build_scratch_bytes() + watch_bytes();
}

bool NeighbourList::needs_rebuild(const double* x, std::size_t n, double radius, double skin) const {
  if (stale_ || skin <= 0.0 || n != count() || radius + skin != radius_at_build_) return true;
  // The watch positions are rounded to single precision, |x_build - x_at_build_| <= watch_error_:
  // a particle that has moved at most skin/2 - watch_error_ from x_at_build_ has moved at most skin/2
  // since the build (theory section 7). The factor (1 - 1e-12) covers the round-off of the double sums below.
  const double allowed = (0.5 * skin - watch_error_) * (1.0 - 1e-12);
  if (!(allowed > 0.0)) return true;
  const double limit2 = allowed * allowed;
  int moved = 0;
#pragma omp parallel for reduction(max : moved) schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = x[3 * i] - static_cast<double>(x_at_build_[3 * i]),
                 dy = x[3 * i + 1] - static_cast<double>(x_at_build_[3 * i + 1]),
                 dz = x[3 * i + 2] - static_cast<double>(x_at_build_[3 * i + 2]);
    // NaN compares false here; the stability check, not the neighbour search, reports it.
    if (dx * dx + dy * dy + dz * dz > limit2) moved = 1;
  }
  return moved != 0;
}

void NeighbourList::rebuild(const double* x, std::size_t n, double radius, double skin, std::size_t query,
                            std::span<double> borrow, const double* point_support) {
  build(x, n, radius + skin, query, borrow, point_support, skin);
  const std::size_t watched = 3 * std::min(n, query);
  x_at_build_.resize(watched);
  double largest = 0.0;
#pragma omp parallel for reduction(max : largest) schedule(static)
  for (std::size_t k = 0; k < watched; ++k) {
    x_at_build_[k] = static_cast<float>(x[k]);  // round to nearest: |error| <= 2^-24 |x| (normal range)
    largest = std::max(largest, std::abs(x[k]));
  }
  // Per coordinate at most 2^-24 of the largest |x| (+ 2^-149, the spacing of the subnormals); the
  // error vector's length at most sqrt(3) times that.
  watch_error_ = std::sqrt(3.0) * (largest * 0x1p-24 + 0x1p-149);
  radius_at_build_ = radius + skin;
  stale_ = false;
  ++builds_;
}

void NeighbourList::build_transient(const double* x, std::size_t n, double radius, double skin, std::size_t query,
                                    std::span<double> borrow, const double* point_support) {
  build(x, n, radius + skin, query, borrow, point_support, skin);
  stale_ = true;  // the watch positions stay those of the last counted build
}

bool NeighbourList::update(const double* x, std::size_t n, double radius, double skin) {
  if (!needs_rebuild(x, n, radius, skin)) return false;
  rebuild(x, n, radius, skin);
  return true;
}

void NeighbourList::build(const double* x, std::size_t n, double radius, std::size_t query,
                          std::span<double> borrow, const double* point_support, double skin) {
  // Bit 31 of base_of_ marks a wide list, so indices must fit in 31 bits.
  if (n >= kWide) throw std::length_error("too many particles");
  const std::size_t nq = std::min(n, query);  // particles that get a list
  end_.resize(nq);
  base_of_.resize(nq);
  const std::size_t nchunks = (nq + kChunk - 1) / kChunk;
  chunks_.resize(nchunks);
  chunk_used_.assign(nchunks, 0);
  chunk_pairs_.assign(nchunks, 0);
  chunk_data_.assign(nchunks, nullptr);
#ifdef _OPENMP
  candidates_.resize(static_cast<std::size_t>(std::max(1, omp_get_max_threads())));
#else
  candidates_.resize(1);
#endif
  if (n == 0) return;

  double lo[3], hi[3];
  {
    double l0 = std::numeric_limits<double>::infinity(), l1 = l0, l2 = l0, h0 = -l0, h1 = -l0, h2 = -l0;
#pragma omp parallel for reduction(min : l0, l1, l2) reduction(max : h0, h1, h2) schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      l0 = std::min(l0, x[3 * i]);
      l1 = std::min(l1, x[3 * i + 1]);
      l2 = std::min(l2, x[3 * i + 2]);
      h0 = std::max(h0, x[3 * i]);
      h1 = std::max(h1, x[3 * i + 1]);
      h2 = std::max(h2, x[3 * i + 2]);
    }
    lo[0] = l0, lo[1] = l1, lo[2] = l2, hi[0] = h0, hi[1] = h1, hi[2] = h2;
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

  cell_start_.assign(ncells + 1, 0);
  // The per-point scratch (20 bytes per point): in the borrowed buffer when it is large enough
  // (the pass scratch, idle while the lists are built, so the scene does not hold both), else in
  // this object's own arrays. Only this function reads it; it is dead once the lists are built.
  std::uint32_t* cell_of;
  std::uint32_t* sorted;
  float* sorted_x;
  if (borrow.size() * sizeof(double) >= n * build_scratch_bytes_per_point()) {
    std::vector<std::uint32_t>().swap(cell_of_);
    std::vector<std::uint32_t>().swap(sorted_);
    std::vector<float>().swap(sorted_x_);
    auto* bytes = reinterpret_cast<unsigned char*>(borrow.data());
    cell_of = reinterpret_cast<std::uint32_t*>(bytes);
    sorted = reinterpret_cast<std::uint32_t*>(bytes + n * sizeof(std::uint32_t));
    sorted_x = reinterpret_cast<float*>(bytes + 2 * n * sizeof(std::uint32_t));
  } else {
    cell_of_.resize(n);
    sorted_.resize(n);
    sorted_x_.resize(3 * n);
    cell_of = cell_of_.data();
    sorted = sorted_.data();
    sorted_x = sorted_x_.data();
  }
  auto cell_coord = [&](double v, int d) {
    return std::min<std::int64_t>(dims[d] - 1, static_cast<std::int64_t>((v - lo[d]) / edge[d]));
  };
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t cx = cell_coord(x[3 * i], 0), cy = cell_coord(x[3 * i + 1], 1),
                       cz = cell_coord(x[3 * i + 2], 2);
    cell_of[i] = static_cast<std::uint32_t>((cz * dims[1] + cy) * dims[0] + cx);
  }
  // Counting sort of particles by cell (stable: ascending index within a cell), with their
  // positions copied next to each other so that a row of three cells is one contiguous run.
  for (std::size_t i = 0; i < n; ++i) ++cell_start_[cell_of[i] + 1];
  for (std::size_t c = 0; c < ncells; ++c) cell_start_[c + 1] += cell_start_[c];
  {
    std::vector<std::uint32_t>& fill = end_;  // used as the cursor array here, overwritten below
    fill.assign(cell_start_.begin(), cell_start_.end() - 1);
    fill.resize(std::max(n, ncells));
    for (std::size_t i = 0; i < n; ++i) sorted[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
    end_.resize(nq);
  }
#pragma omp parallel for schedule(static)
  for (std::size_t s = 0; s < n; ++s)
    for (int d = 0; d < 3; ++d) sorted_x[3 * s + d] = static_cast<float>(x[3 * sorted[s] + d] - lo[d]);

  // Single precision with a margin that keeps the lists a superset of the exact ones: rounding
  // the offsets from the grid origin errs by at most 2^-24 of the extent per coordinate.
  double extent = 0.0;
  for (int d = 0; d < 3; ++d) extent = std::max(extent, hi[d] - lo[d]);
  const double search = radius * (1.0 + 1e-5) + 1e-6 * extent;
  const float r2 = static_cast<float>(search * search);
  // Variable spacing (eq. 140): a pair is kept when closer than (S_i + S_j) / 2 + skin, with the
  // same margin; `radius` is the largest S + skin, so these radii never exceed the cells' reach.
  const bool graded = point_support != nullptr;
  const double pair_margin = search - radius + skin;  // skin plus the single-precision margin
  if (graded) {
    sorted_half_support_.resize(n);
#pragma omp parallel for schedule(static)
    for (std::size_t s = 0; s < n; ++s) sorted_half_support_[s] = static_cast<float>(0.5 * point_support[sorted[s]]);
  } else {
    std::vector<float>().swap(sorted_half_support_);
  }
  const float* half_support = sorted_half_support_.data();

#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t c = 0; c < nchunks; ++c) {
#ifdef _OPENMP
    std::vector<std::uint32_t>& cand = candidates_[static_cast<std::size_t>(omp_get_thread_num())];
#else
    std::vector<std::uint32_t>& cand = candidates_[0];
#endif
    std::vector<std::uint16_t>& out = chunks_[c];
    std::size_t used = 0, listed = 0;
    const std::size_t first = c * kChunk, last = std::min(nq, first + kChunk);
    for (std::size_t i = first; i < last; ++i) {
      std::size_t found = 0;  // i's neighbours, first as full indices in cand
      const std::uint32_t cell = cell_of[i];
      const std::int64_t cx = cell % dims[0], cy = (cell / dims[0]) % dims[1], cz = cell / (dims[0] * dims[1]);
      const float xi = static_cast<float>(x[3 * i] - lo[0]), yi = static_cast<float>(x[3 * i + 1] - lo[1]),
                  zi = static_cast<float>(x[3 * i + 2] - lo[2]);
      const std::int64_t x0 = std::max<std::int64_t>(0, cx - 1), x1 = std::min(dims[0] - 1, cx + 1);
      for (std::int64_t z = std::max<std::int64_t>(0, cz - 1); z <= std::min(dims[2] - 1, cz + 1); ++z)
        for (std::int64_t y = std::max<std::int64_t>(0, cy - 1); y <= std::min(dims[1] - 1, cy + 1); ++y) {
          // Cells x0..x1 of this row are one contiguous run of sorted_.
          const std::size_t row = static_cast<std::size_t>((z * dims[1] + y) * dims[0]);
          const std::uint32_t s0 = cell_start_[row + x0], s1 = cell_start_[row + x1 + 1];
          if (found + (s1 - s0) > cand.size()) cand.resize(2 * (found + (s1 - s0)));
          std::uint32_t* dst = cand.data();
          const float* p = sorted_x;
          if (graded) {
            const float reach_i = static_cast<float>(0.5 * point_support[i] + pair_margin);
            for (std::uint32_t s = s0; s < s1; ++s) {
              const float dx = xi - p[3 * s], dy = yi - p[3 * s + 1], dz = zi - p[3 * s + 2];
              const float reach = reach_i + half_support[s];
              const std::uint32_t j = sorted[s];
              dst[found] = j;
              found += (dx * dx + dy * dy + dz * dz < reach * reach) & (j != i);
            }
          } else {
            for (std::uint32_t s = s0; s < s1; ++s) {
              const float dx = xi - p[3 * s], dy = yi - p[3 * s + 1], dz = zi - p[3 * s + 2];
              const std::uint32_t j = sorted[s];
              dst[found] = j;  // branch-free: kept only when close enough and not i itself
              found += (dx * dx + dy * dy + dz * dz < r2) & (j != i);
            }
          }
        }
      // Encode (section 7): offsets from the smallest index when the list spans at most 65,535
      // indices, else both halves of each index. The order of the neighbours is kept.
      std::uint32_t jmin = found > 0 ? cand[0] : 0u, jmax = jmin;
      for (std::size_t k = 1; k < found; ++k) {
        jmin = std::min(jmin, cand[k]);
        jmax = std::max(jmax, cand[k]);
      }
      const bool wide = jmax - jmin > 0xffffu;
      const std::size_t units = wide ? 2 * found : found;
      if (used + units > out.size()) {
        // Grow by 1/8 at a time (reserve first: resize() alone would double the capacity).
        const std::size_t want = std::max<std::size_t>(used + units, out.size() + out.size() / 8 + 8192);
        out.reserve(want);
        out.resize(want);
      }
      std::uint16_t* dst = out.data() + used;
      if (wide) {
        for (std::size_t k = 0; k < found; ++k) {
          dst[2 * k] = static_cast<std::uint16_t>(cand[k] & 0xffffu);
          dst[2 * k + 1] = static_cast<std::uint16_t>(cand[k] >> 16);
        }
      } else {
        for (std::size_t k = 0; k < found; ++k) dst[k] = static_cast<std::uint16_t>(cand[k] - jmin);
      }
      used += units;
      listed += found;
      base_of_[i] = wide ? kWide : jmin;
      end_[i] = static_cast<std::uint32_t>(used);
    }
    // The growth steps above leave up to 1/8 of a chunk unused (10 % of the list memory after the
    // first build). Trim a chunk that holds more than ~3 % spare to a 1/64 margin: one copy of that
    // chunk, only after a build that grew it, and the next builds fill it in place.
    const std::size_t keep = used + used / 64 + 256;
    if (out.capacity() > keep + keep / 32) {
      std::vector<std::uint16_t> trimmed;
      trimmed.reserve(keep);
      trimmed.assign(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(used));
      trimmed.resize(keep);
      out.swap(trimmed);
    }
    chunk_used_[c] = static_cast<std::uint32_t>(used);
    chunk_pairs_[c] = static_cast<std::uint32_t>(listed);
    chunk_data_[c] = out.data();
  }
}

}  // namespace sphforge
