// Neighbour search: uniform cell list (cell edge = search radius), full neighbour lists in
// compressed-row form. Particle i's neighbours are indices[offsets[i] .. offsets[i+1]), in
// ascending cell order, so every pair loop sums in a fixed order and results do not depend on
// the number of threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sphforge {

class NeighbourList {
 public:
  /// Verlet-skin rebuild policy: the lists hold all pairs closer than radius + skin, so they stay
  /// complete for `radius` until some particle has moved more than skin/2 since the last build.
  /// Rebuilds when needed and returns true if it did. `skin` = 0 rebuilds every call.
  bool update(const double* x, std::size_t count, double radius, double skin);
  long long builds() const { return builds_; }

  /// Builds lists of all j != i with |x_i - x_j| < radius. x: 3 doubles per particle.
  /// Allocation-free once the arrays have grown to their working size.
  void build(const double* x, std::size_t count, double radius);

  std::size_t count() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  const std::uint32_t* begin(std::size_t i) const { return indices_.data() + offsets_[i]; }
  const std::uint32_t* end(std::size_t i) const { return indices_.data() + offsets_[i + 1]; }
  std::size_t pairs() const { return indices_.size(); }
  std::size_t bytes() const;

 private:
  std::vector<std::size_t> offsets_;
  std::vector<std::uint32_t> indices_;
  // Cell list scratch.
  std::vector<std::uint32_t> cell_of_;       // cell index of each particle
  std::vector<std::uint32_t> cell_start_;    // first slot of each cell in sorted_
  std::vector<std::uint32_t> sorted_;        // particle indices sorted by cell
  std::vector<std::uint32_t> neighbour_count_;
  std::vector<double> x_at_build_;            // positions when the lists were built
  double radius_at_build_ = -1.0;
  long long builds_ = 0;
};

}  // namespace sphforge
