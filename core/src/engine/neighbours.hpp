// Neighbour search: uniform cell list (cell edge = search radius), full neighbour lists.
// Particle i's neighbours are begin(i) .. end(i), in ascending cell order (cells by z, y, x;
// particles within a cell by index), so every pair loop sums in a fixed order and results do not
// depend on the number of threads.
//
// Storage: the lists of particles [c * kChunk, (c + 1) * kChunk) lie back to back in chunk c's
// own array, so that the chunks are filled in parallel in a single sweep (no counting pass), and
// end_[i] is the end of particle i's list within its chunk. A chunk that grew during a build is
// trimmed to a 1/64 margin afterwards (one copy), so that the lists hold little unused memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sphforge {

class NeighbourList {
 public:
  static constexpr std::size_t kChunk = 1024;  ///< particles per storage chunk (a power of 2)

  /// Verlet-skin rebuild policy: the lists hold all pairs closer than radius + skin, so they stay
  /// complete for `radius` until some particle has moved more than skin/2 since the last build.
  /// Rebuilds when needed and returns true if it did. `skin` = 0 rebuilds every call.
  bool update(const double* x, std::size_t count, double radius, double skin);
  /// The test of update(): true when the lists must be rebuilt before they are used at x.
  bool needs_rebuild(const double* x, std::size_t count, double radius, double skin) const;
  /// The rebuild of update(), unconditionally (counts as a build). With `query` < count, lists
  /// are built only for particles [0, query), whose neighbours may be any of the `count` points
  /// (symmetry ghosts [query, count): engine/symmetry.hpp); needs_rebuild() then watches [0, query).
  void rebuild(const double* x, std::size_t count, double radius, double skin, std::size_t query = SIZE_MAX);
  long long builds() const { return builds_; }

  /// Builds lists of all j != i with |x_i - x_j| < radius (possibly a few more pairs closer than
  /// radius (1 + 1e-5) + 1e-6 * the cloud's extent: the search runs in single precision with that
  /// margin, so the lists are always a superset). x: 3 doubles per particle.
  /// Allocation-free once the arrays have grown to their working size.
  void build(const double* x, std::size_t count, double radius, std::size_t query = SIZE_MAX);

  std::size_t count() const { return end_.size(); }
  const std::uint32_t* begin(std::size_t i) const {
    return base_[i / kChunk] + ((i % kChunk) != 0 ? end_[i - 1] : 0u);
  }
  const std::uint32_t* end(std::size_t i) const { return base_[i / kChunk] + end_[i]; }
  std::size_t pairs() const;
  /// Memory held (lists, cell-list scratch, positions at the last build), in bytes: the sum of
  /// the four parts below.
  std::size_t bytes() const;
  /// The list entries (capacity of the chunks; pairs() * 4 of it in use).
  std::size_t list_bytes() const;
  /// The per-particle list ends and the per-chunk bookkeeping.
  std::size_t index_bytes() const;
  /// Scratch of the cell-list build (cell of each particle, cell starts, sorted indices and positions).
  std::size_t build_scratch_bytes() const;
  /// The positions at the last build that needs_rebuild() compares with.
  std::size_t watch_bytes() const;

 private:
  std::vector<std::uint32_t> end_;                 // end of i's list within its chunk
  std::vector<std::vector<std::uint32_t>> chunks_;  // the lists, kChunk particles per chunk
  std::vector<std::uint32_t> chunk_used_;           // entries in use in each chunk
  std::vector<const std::uint32_t*> base_;          // chunks_[c].data()
  // Cell list scratch.
  std::vector<std::uint32_t> cell_of_;     // cell index of each particle
  std::vector<std::uint32_t> cell_start_;  // first slot of each cell in sorted_
  std::vector<std::uint32_t> sorted_;      // particle indices sorted by cell
  std::vector<float> sorted_x_;            // their positions relative to the grid origin, 3 per slot
  std::vector<double> x_at_build_;         // positions when the lists were built
  double radius_at_build_ = -1.0;
  long long builds_ = 0;
};

}  // namespace sphforge
