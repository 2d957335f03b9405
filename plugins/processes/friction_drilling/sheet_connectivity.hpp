// Which sheet particles are still joined to the clamped rim (docs/theory.md eq. 127a): the
// friction-drilling bushing counts only those (eqs. 127-129), not material that the drill has torn
// off and dragged below its tip. Plain code on the public headers, free of the plugin machinery, so
// that tests/unit/test_friction_drilling_bushing.cpp tests it on synthetic particle sets.
//
// Link (eq. 127a): two sheet particles i, j are linked when |x_i - x_j| < L (the link distance) and
// their bond is not broken under the core's rule (sphforge/bond_rule.hpp, eqs. 111-112: both failed
// and the pair under tension). A particle is connected when a chain of links joins it to a seed
// (a clamped particle, eq. 121). In a sector of 360/N deg (N > 1) the chain may also pass through
// the cut planes: i is linked to the rotated image Q_k x_j of j (rotation by +-360/N deg about z),
// with j's stress rotated with it; a full disc (N = 1) has no images.
//
// Method: union-find over the links, with the candidate pairs from a uniform grid of cells of size L
// (hashed into a table of about 2 buckets per particle, so a particle far from the rest costs no
// memory); O(N) for particles at bounded density. The arrays are members and keep their capacity
// between calls (cleared, not reallocated).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Core>

#include "sphforge/bond_rule.hpp"

namespace sphforge::friction_drilling {

/// The particles a connectivity query looks at: arrays of the core's SoA layout.
struct SheetParticles {
  std::size_t count = 0;
  const double* position = nullptr;        ///< 3 per particle, m
  const std::int64_t* seed = nullptr;      ///< 1 per particle: nonzero = joined by definition (the clamped rim)
  const double* failed = nullptr;          ///< 1 per particle (field `failed`); null: no bond can break
  const double* pressure = nullptr;        ///< 1 per particle, Pa; read only with `failed`
  const double* deviatoric_stress = nullptr;  ///< 6 per particle (xx yy zz xy yz xz), Pa; only with `failed`
  /// Per-particle link distance (variable spacing: 1.5 s_i), m; null: every pair has link_distance.
  /// A pair is then linked when closer than the mean of its two, and link_distance must be the largest.
  const double* link = nullptr;
};

class SheetConnectivity {
 public:
  /// Finds the particles joined to a seed through links shorter than `link_distance` (m) that the
  /// bond rule has not broken, for a sector of 360/`sector_count` deg (1: the full disc). Returns
  /// how many are connected; connected(i) then tells each particle.
  std::size_t compute(const SheetParticles& s, double link_distance, int sector_count) {
    const std::size_t n = s.count;
    connected_.assign(n, 0);
    if (n == 0) return 0;
    const double L = link_distance, inv = 1.0 / L;
    parent_.resize(n);
    for (std::size_t i = 0; i < n; ++i) parent_[i] = i;
    size_.assign(n, 1);

    // Cauchy stress sigma = S - p I, which the bond rule reads (only when particles can fail).
    const bool failure = s.failed != nullptr;
    if (failure) {
      sigma_.resize(6 * n);
      for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 6; ++c) sigma_[6 * i + c] = s.deviatoric_stress[6 * i + c] - (c < 3 ? s.pressure[i] : 0.0);
    }

    // Cell grid (cell size L), counting-sorted by the hashed cell of each particle.
    std::size_t buckets = 1;
    while (buckets < 2 * n) buckets <<= 1;
    mask_ = buckets - 1;
    bucket_start_.assign(buckets + 1, 0);
    bucket_of_.resize(n);
    lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    hi_ = -lo_;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d x(s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2]);
      lo_ = lo_.cwiseMin(x);
      hi_ = hi_.cwiseMax(x);
      bucket_of_[i] = bucket(cell(x, inv));
      ++bucket_start_[bucket_of_[i] + 1];
    }
    for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
    sorted_.resize(n);
    fill_.assign(bucket_start_.begin(), bucket_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted_[fill_[bucket_of_[i]]++] = i;

    // Links inside the simulated part (each pair once: j > i).
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d xi(s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2]);
      for_each_candidate(xi, inv, [&](std::size_t j) {
        if (j <= i) return;
        const Eigen::Vector3d xj(s.position[3 * j], s.position[3 * j + 1], s.position[3 * j + 2]);
        const Eigen::Vector3d d = xi - xj;
        const double Lij = s.link ? 0.5 * (s.link[i] + s.link[j]) : L;
        if (d.squaredNorm() >= Lij * Lij) return;
        if (failure && bond_factor(s.failed[i], s.failed[j], &sigma_[6 * i], &sigma_[6 * j], d.x(), d.y(), d.z()) == 0.0)
          return;
        unite(i, j);
      });
    }

    // Links through the cut planes of a sector: i with the image Q x_j of j. |x_i - Q x_j| =
    // |Q^T x_i - x_j|, so the grid is searched about Q^T x_i; only points within L of the particles'
    // bounding box can find anything (those near a cut plane). N = 2: +180 and -180 deg coincide.
    if (sector_count > 1) {
      const double angle = 2.0 * std::numbers::pi / sector_count;
      const int images = sector_count == 2 ? 1 : 2;
      for (int k = 0; k < images; ++k) {
        const double a = k == 0 ? angle : -angle, c = std::cos(a), sn = std::sin(a);
        Eigen::Matrix3d Q;
        Q << c, -sn, 0.0, sn, c, 0.0, 0.0, 0.0, 1.0;
        for (std::size_t i = 0; i < n; ++i) {
          const Eigen::Vector3d xi(s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2]);
          const Eigen::Vector3d q = Q.transpose() * xi;
          if ((q.array() < lo_.array() - L).any() || (q.array() > hi_.array() + L).any()) continue;
          for_each_candidate(q, inv, [&](std::size_t j) {
            const Eigen::Vector3d xj(s.position[3 * j], s.position[3 * j + 1], s.position[3 * j + 2]);
            const Eigen::Vector3d d = xi - Q * xj;  // x_i minus the image of x_j
            const double Lij = s.link ? 0.5 * (s.link[i] + s.link[j]) : L;
            if (d.squaredNorm() >= Lij * Lij) return;
            if (failure) {
              double sj[6];
              rotate_stress(Q, &sigma_[6 * j], sj);
              if (bond_factor(s.failed[i], s.failed[j], &sigma_[6 * i], sj, d.x(), d.y(), d.z()) == 0.0) return;
            }
            unite(i, j);
          });
        }
      }
    }

    // Connected: in the set of a seed.
    root_seeded_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (s.seed[i]) root_seeded_[find(i)] = 1;
    std::size_t joined = 0;
    for (std::size_t i = 0; i < n; ++i) {
      connected_[i] = root_seeded_[find(i)];
      joined += connected_[i];
    }
    return joined;
  }

  /// After compute(): true when particle i is joined to a seed.
  bool connected(std::size_t i) const { return connected_[i] != 0; }

 private:
  using Cell = Eigen::Matrix<std::int64_t, 3, 1>;

  static Cell cell(const Eigen::Vector3d& x, double inv) {
    return Cell(static_cast<std::int64_t>(std::floor(x.x() * inv)), static_cast<std::int64_t>(std::floor(x.y() * inv)),
                static_cast<std::int64_t>(std::floor(x.z() * inv)));
  }
  std::size_t bucket(const Cell& c) const {
    const std::uint64_t h = static_cast<std::uint64_t>(c.x()) * 73856093ULL ^ static_cast<std::uint64_t>(c.y()) * 19349663ULL ^
                            static_cast<std::uint64_t>(c.z()) * 83492791ULL;
    return static_cast<std::size_t>((h ^ (h >> 29)) & mask_);
  }

  /// Calls f(j) for every particle j in the 27 cells about x (a hash collision only adds candidates,
  /// which the caller's distance test rejects; a bucket met twice gives a pair twice, harmless).
  template <class F>
  void for_each_candidate(const Eigen::Vector3d& x, double inv, F&& f) const {
    const Cell c = cell(x, inv);
    for (std::int64_t dz = -1; dz <= 1; ++dz)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const std::size_t b = bucket(Cell(c.x() + dx, c.y() + dy, c.z() + dz));
          for (std::size_t k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) f(sorted_[k]);
        }
  }

  /// Q sigma Q^T for a symmetric tensor stored xx yy zz xy yz xz.
  static void rotate_stress(const Eigen::Matrix3d& Q, const double* s, double* out) {
    Eigen::Matrix3d S;
    S << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
    const Eigen::Matrix3d R = Q * S * Q.transpose();
    out[0] = R(0, 0);
    out[1] = R(1, 1);
    out[2] = R(2, 2);
    out[3] = R(0, 1);
    out[4] = R(1, 2);
    out[5] = R(0, 2);
  }

  std::size_t find(std::size_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];  // path halving
      i = parent_[i];
    }
    return i;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size_[a] > size_[b]) std::swap(a, b);
    parent_[a] = b;  // union by size + path halving: near-constant time per operation
    size_[b] += size_[a];
  }

  std::vector<std::size_t> parent_, size_, bucket_start_, bucket_of_, sorted_, fill_;
  std::vector<double> sigma_;
  std::vector<unsigned char> connected_, root_seeded_;
  std::size_t mask_ = 0;
  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();
};

/// The bushing band's extremes (eq. 127): the rank-th highest and lowest z of the particles with
/// r_in <= r <= r_out (r about the z axis), counting only connected ones when `joined` is given.
struct BandExtremes {
  bool found = false;  ///< the band holds at least `rank` counted particles
  double z_high = 0.0, z_low = 0.0;
  std::size_t detached = 0;  ///< particles in the band that are not connected (0 without `joined`)
};

/// `highest`, `lowest`: scratch, kept by the caller so that their storage is reused.
inline BandExtremes band_extremes(const SheetParticles& s, const SheetConnectivity* joined, double r_in, double r_out,
                                  std::size_t rank, std::vector<double>& highest, std::vector<double>& lowest) {
  // Keeps the `rank` most extreme values (by `better`) in `list`, sorted best first.
  auto keep = [rank](std::vector<double>& list, double value, auto better) {
    if (list.size() == rank && !better(value, list.back())) return;
    list.insert(std::lower_bound(list.begin(), list.end(), value, better), value);
    if (list.size() > rank) list.pop_back();
  };
  highest.clear();
  lowest.clear();
  BandExtremes e;
  for (std::size_t i = 0; i < s.count; ++i) {
    const double r = std::hypot(s.position[3 * i], s.position[3 * i + 1]);
    if (r < r_in || r > r_out) continue;
    if (joined && !joined->connected(i)) {
      ++e.detached;
      continue;
    }
    keep(highest, s.position[3 * i + 2], std::greater<double>());
    keep(lowest, s.position[3 * i + 2], std::less<double>());
  }
  if (rank > 0 && highest.size() == rank) {
    e.found = true;
    e.z_high = highest.back();
    e.z_low = lowest.back();
  }
  return e;
}

}  // namespace sphforge::friction_drilling
