// Neighbour search: uniform cell list (cell edge = search radius), full neighbour lists.
// Particle i's neighbours are row(i)[0] .. row(i)[size(i) - 1], in ascending cell order (cells by
// z, y, x; particles within a cell by index), so every pair loop sums in a fixed order and results
// do not depend on the number of threads.
//
// Storage (docs/theory.md section 7): 16-bit entries. After the Morton reordering
// (engine/reorder.hpp) a particle's neighbours lie within a few thousand indices of each other, so
// a list is stored as its smallest index, the base, and one 16-bit offset per neighbour
// (j = base + offset): 2 bytes per pair instead of 4. A list that spans more than 65,535 indices
// (under 1 % of the particles in the benchmark block) is "wide": each neighbour is then two 16-bit
// halves (low, high) of its index. The pair loops decode() a particle's list into 32-bit indices
// on the stack first and read the same neighbours in the same order either way.
// The lists of particles [c * kChunk, (c + 1) * kChunk) lie back to back in chunk c's own array,
// so that the chunks are filled in parallel in a single sweep (no counting pass), and end_[i] is
// the end of particle i's list within its chunk (in 16-bit units). A chunk that grew during a
// build is trimmed to a 1/64 margin afterwards (one copy), so that the lists hold little unused
// memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
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
  /// `borrow`: storage idle during the build (the caller's pass scratch) that the build may use for
  /// its scratch (build_scratch_bytes_per_point() per point) instead of holding its own; its
  /// contents are overwritten.
  /// `point_support` (default null): per-point kernel support radii 2 h_i of a scene of several
  /// spacings (eq. 140); a pair is then listed when closer than (S_i + S_j) / 2 + skin, the support
  /// of its h_ij plus the skin, and `radius` must be the largest S_i.
  void rebuild(const double* x, std::size_t count, double radius, double skin, std::size_t query = SIZE_MAX,
               std::span<double> borrow = {}, const double* point_support = nullptr);
  /// Bytes of build scratch per point (cell, sorted index, 3 single-precision coordinates).
  static constexpr std::size_t build_scratch_bytes_per_point() {
    return 2 * sizeof(std::uint32_t) + 3 * sizeof(float);
  }
  long long builds() const { return builds_; }
  /// Restart (docs/checkpoints.md): the next needs_rebuild() is true. A checkpoint marks the lists
  /// stale in the run that writes it, and a restarted run starts without lists, so both rebuild
  /// at the same step from the same positions.
  void mark_stale() { stale_ = true; }
  /// Restart: the build count of the run that wrote the checkpoint (the reordering schedule
  /// follows it, Simulation::kReorderEveryBuilds).
  void continue_count(long long builds) { builds_ = builds; }
  /// A build for one evaluation outside the step (an output frame's velocity gradient): lists for
  /// x as rebuild() makes them, but it does not count as a build and leaves the lists marked stale,
  /// so that the next needs_rebuild() is true and the step rebuilds exactly where it would have
  /// without this build (same build count, same watch positions, same reordering schedule).
  void build_transient(const double* x, std::size_t count, double radius, double skin,
                       std::size_t query = SIZE_MAX, std::span<double> borrow = {},
                       const double* point_support = nullptr);

  /// Builds lists of all j != i with |x_i - x_j| < radius (possibly a few more pairs closer than
  /// radius (1 + 1e-5) + 1e-6 * the cloud's extent: the search runs in single precision with that
  /// margin, so the lists are always a superset). x: 3 doubles per particle.
  /// Allocation-free once the arrays have grown to their working size.
  /// `point_support` (default null): as for rebuild(), with `radius` = the largest S_i + skin and
  /// `skin` the part of it that every pair gets on top of its own support.
  void build(const double* x, std::size_t count, double radius, std::size_t query = SIZE_MAX,
             std::span<double> borrow = {}, const double* point_support = nullptr, double skin = 0.0);

  std::size_t count() const { return end_.size(); }

  /// Particle i's list: `count` neighbours, the k-th is base + entries[k] (narrow) or
  /// entries[2k] | entries[2k + 1] << 16 (wide).
  struct Row {
    const std::uint16_t* entries;
    std::uint32_t base;
    std::uint32_t count;
    bool wide;
    std::uint32_t operator[](std::size_t k) const {
      return wide ? static_cast<std::uint32_t>(entries[2 * k]) | static_cast<std::uint32_t>(entries[2 * k + 1]) << 16
                  : base + entries[k];
    }
  };
  Row row(std::size_t i) const {
    const std::uint16_t* first = chunk_data_[i / kChunk] + ((i % kChunk) != 0 ? end_[i - 1] : 0u);
    const std::uint32_t units = static_cast<std::uint32_t>(chunk_data_[i / kChunk] + end_[i] - first);
    const bool wide = (base_of_[i] & kWide) != 0;
    return {first, wide ? 0u : base_of_[i], wide ? units / 2 : units, wide};
  }
  /// Writes i's neighbour indices, in list order, to out (room for size(i)); returns their number.
  /// The pair loops decode a list into a small buffer and then run over plain 32-bit indices: the
  /// same loop, vectorised the same way, as over a 32-bit list, so the sums are the same to the bit.
  std::size_t decode(std::size_t i, std::uint32_t* out) const {
    const Row r = row(i);
    if (r.wide)
      for (std::uint32_t k = 0; k < r.count; ++k) out[k] = r[k];
    else
      for (std::uint32_t k = 0; k < r.count; ++k) out[k] = r.base + r.entries[k];
    return r.count;
  }
  /// Number of neighbours of i.
  std::size_t size(std::size_t i) const { return row(i).count; }
  /// Calls f(j) for every neighbour j of i, in list order (for the loops that are not hot).
  template <class F>
  void for_each(std::size_t i, F&& f) const {
    const Row r = row(i);
    if (r.wide)
      for (std::uint32_t k = 0; k < r.count; ++k) f(static_cast<std::size_t>(r[k]));
    else
      for (std::uint32_t k = 0; k < r.count; ++k) f(static_cast<std::size_t>(r.base) + r.entries[k]);
  }
  /// Neighbour pairs (list entries, i.e. sum of size(i)).
  std::size_t pairs() const;
  /// Particles whose list is wide (stored with 4 bytes per neighbour).
  std::size_t wide_rows() const;
  /// Memory held (lists, cell-list scratch, positions at the last build), in bytes: the sum of
  /// the four parts below.
  std::size_t bytes() const;
  /// The list entries (capacity of the chunks; about pairs() * 2 of it in use).
  std::size_t list_bytes() const;
  /// The per-particle list ends and bases, the per-chunk bookkeeping and the encoding scratch.
  std::size_t index_bytes() const;
  /// Scratch of the cell-list build (cell of each particle, cell starts, sorted indices and positions).
  std::size_t build_scratch_bytes() const;
  /// The positions at the last build that needs_rebuild() compares with.
  std::size_t watch_bytes() const;

 private:
  static constexpr std::uint32_t kWide = 0x80000000u;  ///< base_of_: the list is wide
  std::vector<std::uint32_t> end_;       // end of i's list within its chunk, in 16-bit units
  std::vector<std::uint32_t> base_of_;   // smallest neighbour index of i, or kWide
  std::vector<std::vector<std::uint16_t>> chunks_;  // the lists, kChunk particles per chunk
  std::vector<std::uint32_t> chunk_used_;           // 16-bit units in use in each chunk
  std::vector<std::uint32_t> chunk_pairs_;          // neighbours listed in each chunk
  std::vector<const std::uint16_t*> chunk_data_;    // chunks_[c].data()
  std::vector<std::vector<std::uint32_t>> candidates_;  // per thread: one particle's list before encoding
  // Cell list scratch. The per-point arrays live in a borrowed buffer when build() is given one
  // large enough (then these three stay empty), else here.
  std::vector<std::uint32_t> cell_of_;     // cell index of each particle
  std::vector<std::uint32_t> cell_start_;  // first slot of each cell in sorted_
  std::vector<std::uint32_t> sorted_;      // particle indices sorted by cell
  std::vector<float> sorted_x_;            // their positions relative to the grid origin, 3 per slot
  std::vector<float> sorted_half_support_;  // variable spacing: S_j / 2 per slot (eq. 140)
  // Positions when the lists were built, in single precision (12 bytes per particle instead of 24);
  // watch_error_ bounds |x_build - x_at_build_| (rounding, theory section 7), which needs_rebuild()
  // takes off the skin/2 it allows, so that the lists stay complete for `radius`.
  std::vector<float> x_at_build_;
  double watch_error_ = 0.0;
  double radius_at_build_ = -1.0;
  long long builds_ = 0;
  bool stale_ = false;  ///< set by build_transient(): the next needs_rebuild() is true
};

/// One particle's neighbour list decoded to 32-bit indices (theory section 7): on the stack for the
/// usual lengths, in a per-thread buffer for a longer list (grown once). The pair loops
/// (engine/sph_operators.cpp, engine/second_order_gradient.cpp) then run over plain indices.
struct DecodedList {
  static constexpr std::size_t kInline = 1024;
  std::uint32_t local[kInline];
  const std::uint32_t* indices;
  std::size_t count;
  DecodedList(const NeighbourList& nl, std::size_t i) {
    const std::size_t n = nl.size(i);
    std::uint32_t* out = local;
    if (n > kInline) {
      static thread_local std::vector<std::uint32_t> spill;
      if (spill.size() < n) spill.resize(n);
      out = spill.data();
    }
    count = nl.decode(i, out);
    indices = out;
  }
};

}  // namespace sphforge
