// Symmetry: mirror planes and rotationally periodic sectors about the z axis (docs/theory.md,
// section 11, eqs. 28-32). Only the particles inside the symmetry region are simulated ("real");
// their images across the cuts ("ghosts") complete the neighbourhoods of the real particles near
// a cut. Ghosts live in separate, extended copies of the arrays the pair passes read (x, v, m, rho,
// V, A = sigma C, R; T, k for heat): the real particles are [0, n), the ghosts [n, n + g). The
// field registry, the outputs and the processes see the real particles only.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace sphforge {

class FieldRegistry;

/// numerics.symmetry of a case.
struct SymmetrySettings {
  struct Plane {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit; points INTO the simulated half-space
  };
  std::vector<Plane> mirror_planes;  ///< pairwise orthogonal, at most 3
  double sector_angle_rad = 0.0;     ///< 0: no sector; else 2 pi / N, N >= 2 integer
  bool active() const { return !mirror_planes.empty() || sector_angle_rad > 0.0; }
};

/// An isometry x -> Q x + t of the symmetry group (eq. 28).
struct SymmetryImage {
  Eigen::Matrix3d Q = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

class Symmetry {
 public:
  Symmetry() = default;
  /// Throws std::invalid_argument on an unsupported combination (see docs/theory.md section 11).
  explicit Symmetry(const SymmetrySettings& settings);

  bool active() const { return settings_.active(); }
  const SymmetrySettings& settings() const { return settings_; }
  /// The images other than the identity: every product of a sector rotation R^k (k = 0 .. N-1)
  /// and a subset of the mirror reflections (eq. 29).
  const std::vector<SymmetryImage>& images() const { return images_; }
  /// Full body over simulated part: N 2^planes (reaction forces, masses of the full body).
  double multiplier() const { return static_cast<double>(images_.size() + 1); }

  /// True when x lies in the simulated region: n . (x - p) >= 0 for every plane and the polar
  /// angle in [0, angle) for a sector (the axis itself belongs to it) (eq. 30).
  bool inside(const Eigen::Vector3d& x) const;
  /// A lower bound of the distance from y to the simulated region (0 inside).
  double distance_bound(const Eigen::Vector3d& y) const;

  /// Two particles of a scene on one spot (closer than `tolerance`), directly or through the group:
  /// particle i and the image Q x_j + t of particle j. Such a pair doubles the mass there for the
  /// whole run, since nothing separates it (the kernel's gradient vanishes at r = 0); a lattice
  /// site on a cut does it, kept once as itself and once, after round-off, as its twin on the other
  /// cut (docs/theory.md eq. 30a). Returns the first pair (i, j) found, or (n, n) when there is none.
  /// Works without symmetry too (then only direct pairs). Searched with the core's cell list
  /// (engine/neighbours.hpp) of radius `search_radius` >= `tolerance` (half the spacing: a lattice
  /// then lists almost no pair).
  std::pair<std::size_t, std::size_t> find_coincident(const std::vector<Eigen::Vector3d>& x, double search_radius,
                                                      double tolerance) const;

  /// Moves every real particle in [0, n) that left the region back into it: the group element
  /// that maps it inside is applied to all of its fields (position: Q x + t; other 3-component
  /// fields Q v; 6-component symmetric tensors Q S Q^T; 9-component tensors Q A Q^T; other
  /// shapes unchanged). Returns the number of particles moved.
  std::size_t wrap(FieldRegistry& fields, std::size_t n) const { return wrap(fields, 0, n); }
  /// The same for the particles [first, last) (e.g. a tool-attached thermal body, every step).
  std::size_t wrap(FieldRegistry& fields, std::size_t first, std::size_t last) const;
  /// wrap(fields, n), and the moves made: (particle, index into images()) for each particle moved,
  /// for per-particle state kept outside the registry (the contact pass's friction memory).
  std::size_t wrap(FieldRegistry& fields, std::size_t n, std::vector<std::pair<std::size_t, std::size_t>>& moves) const;

  /// Chooses the ghosts: every image of a real particle closer than `range` (kernel support +
  /// skin) to the region, except images that coincide with their source (a particle on a cut).
  void select(const double* x, std::size_t n, double range);
  std::size_t ghost_count() const { return source_.size(); }
  const std::vector<std::uint32_t>& sources() const { return source_; }
  const std::vector<std::uint16_t>& image_of_ghost() const { return image_; }

  // Ghost refresh: array a holds (n + g) entries of the given shape; the real part [0, n) is
  // current and the ghost part [n, n + g) is written from the sources (eq. 31).
  void fill_positions(double* x, std::size_t n) const;    ///< Q x + t
  void fill_vectors(double* v, std::size_t n) const;      ///< Q v
  void fill_scalars(double* s, std::size_t n) const;      ///< copy
  void fill_symmetric(double* S, std::size_t n) const;    ///< Q S Q^T, 6 (xx yy zz xy yz xz)
  void fill_tensors(double* A, std::size_t n) const;      ///< Q A Q^T, 9 row-major

  // The transforms of one value (tests, wrap).
  static void transform_vector(const Eigen::Matrix3d& Q, const double* in, double* out);
  static void transform_symmetric(const Eigen::Matrix3d& Q, const double* in, double* out);
  static void transform_tensor(const Eigen::Matrix3d& Q, const double* in, double* out);

 private:
  std::size_t wrap_range(FieldRegistry& fields, std::size_t first, std::size_t last,
                         std::vector<std::pair<std::size_t, std::size_t>>& moves) const;
  SymmetrySettings settings_;
  int sectors_ = 1;  ///< N
  std::vector<SymmetryImage> images_;
  std::vector<std::uint32_t> source_;
  std::vector<std::uint16_t> image_;
};

}  // namespace sphforge
