// Neighbour lists (engine/neighbours.hpp, docs/theory.md section 7): the 16-bit encoding (offsets
// from the list's smallest index, or both halves of each index for a "wide" list) must give back
// exactly the pairs of a brute-force search, in the documented order (ascending cell, then index),
// whichever form a list takes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/neighbours.hpp"
#include "engine/sph_operators.hpp"
#include "sphforge/kernels.hpp"

using namespace sphforge;

namespace {

// A 50 x 50 x 30 lattice (75,000 points, spacing 1) in lexicographic order, so that most lists
// span a few thousand indices (narrow). Particles 0 and n-1 swap places: the last index then sits
// at the lattice's corner, and the lists of the corner's neighbours span more than 65,535 indices
// (wide). A small deterministic jitter keeps distances off the radius.
std::vector<double> lattice(std::size_t& n) {
  const int nx = 50, ny = 50, nz = 30;
  n = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<double> x(3 * n);
  std::size_t i = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int l = 0; l < nx; ++l, ++i) {
        const double jitter = 0.01 * std::sin(0.37 * static_cast<double>(i));
        x[3 * i] = l + jitter;
        x[3 * i + 1] = j - jitter;
        x[3 * i + 2] = k + 0.5 * jitter;
      }
  for (int d = 0; d < 3; ++d) std::swap(x[d], x[3 * (n - 1) + d]);
  return x;
}

double distance(const std::vector<double>& x, std::size_t i, std::size_t j) {
  const double d0 = x[3 * i] - x[3 * j], d1 = x[3 * i + 1] - x[3 * j + 1], d2 = x[3 * i + 2] - x[3 * j + 2];
  return std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

}  // namespace

TEST(NeighbourLists, EncodedListsHoldExactlyTheBruteForcePairsInCellOrder) {
  std::size_t n = 0;
  const std::vector<double> x = lattice(n);
  const double radius = 2.6;  // 2h at h = 1.3 dx, the default kernel support
  NeighbourList nl;
  nl.build(x.data(), n, radius);
  ASSERT_EQ(nl.count(), n);
  // The corner's neighbours 1, 50, 2500, ... list both n - 1 and indices near 0: wide lists.
  EXPECT_GT(nl.wide_rows(), 0u);
  EXPECT_LT(nl.wide_rows(), n / 100);  // and only those: every other list spans < 65,536 indices

  // The grid the search uses (cells of edge `radius` over the bounding box, x fastest), to check
  // the documented order: ascending cell, then ascending index within a cell.
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = hi[d] = x[d];
    for (std::size_t i = 0; i < n; ++i) lo[d] = std::min(lo[d], x[3 * i + d]), hi[d] = std::max(hi[d], x[3 * i + d]);
  }
  std::int64_t dims[3];
  for (int d = 0; d < 3; ++d) dims[d] = static_cast<std::int64_t>((hi[d] - lo[d]) / radius) + 1;
  auto cell = [&](std::size_t j) {
    std::int64_t c[3];
    for (int d = 0; d < 3; ++d)
      c[d] = std::min<std::int64_t>(dims[d] - 1, static_cast<std::int64_t>((x[3 * j + d] - lo[d]) / radius));
    return (c[2] * dims[1] + c[1]) * dims[0] + c[0];
  };
  // The search runs in single precision with a documented margin (neighbours.hpp, build()): a
  // listed pair may be up to radius (1 + 1e-5) + 1e-6 * extent apart, never farther.
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const double margin = radius * (1.0 + 1e-5) + 1e-6 * extent;

  std::size_t total = 0, checked = 0, wide_checked = 0;
  for (std::size_t i = 0; i < n; ++i) total += nl.size(i);
  EXPECT_EQ(total, nl.pairs());
  // Brute force for every 37th particle and for the corner's surroundings (the wide lists).
  std::vector<std::size_t> sample;
  for (std::size_t i = 0; i < n; i += 37) sample.push_back(i);
  for (std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{50}, std::size_t{51},
                        std::size_t{2500}, std::size_t{2551}, n - 1})
    sample.push_back(i);
  for (const std::size_t i : sample) {
    const NeighbourList::Row row = nl.row(i);
    wide_checked += row.wide ? 1 : 0;
    std::vector<std::size_t> listed;
    nl.for_each(i, [&](std::size_t j) { listed.push_back(j); });
    ASSERT_EQ(listed.size(), row.count);
    for (std::size_t k = 0; k < listed.size(); ++k) {
      ASSERT_EQ(listed[k], row[k]) << "for_each and Row::operator[] disagree at particle " << i;
      ASSERT_LT(listed[k], n);
      ASSERT_NE(listed[k], i);
      EXPECT_LT(distance(x, i, listed[k]), margin) << "pair " << i << "-" << listed[k];
      if (k > 0)
        ASSERT_LT(std::make_pair(cell(listed[k - 1]), listed[k - 1]), std::make_pair(cell(listed[k]), listed[k]))
            << "list of " << i << " not in (cell, index) order at " << k;
    }
    std::vector<std::size_t> sorted = listed;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t j = 0; j < n; ++j)
      if (j != i && distance(x, i, j) < radius)
        EXPECT_TRUE(std::binary_search(sorted.begin(), sorted.end(), j)) << "pair " << i << "-" << j << " missing";
    ++checked;
  }
  EXPECT_GT(wide_checked, 0u);  // the sample did exercise the wide form
  EXPECT_GT(checked, 2000u);
}

TEST(NeighbourLists, ChunksAreTrimmedAfterTheFirstBuild) {
  // The growth steps of the first build leave spare room; the trim brings every chunk to within
  // 1/64 + 256 entries of its use, so the list memory is at most that above 2 bytes per entry (plus
  // 4 more bytes per entry of a wide list).
  std::size_t n = 0;
  const std::vector<double> x = lattice(n);
  NeighbourList nl;
  nl.build(x.data(), n, 2.6);
  std::size_t units = 0;
  for (std::size_t i = 0; i < n; ++i) units += nl.row(i).wide ? 2 * nl.size(i) : nl.size(i);
  const std::size_t chunks = (n + NeighbourList::kChunk - 1) / NeighbourList::kChunk;
  // 1/64 of the units plus 256 per chunk is the trim's margin; a chunk is left alone while its
  // spare room stays below 1/32 of that, hence the factor (1 + 1/32).
  const double bound = (units + units / 64.0 + 256.0 * chunks) * (1.0 + 1.0 / 32.0) * sizeof(std::uint16_t);
  EXPECT_LE(static_cast<double>(nl.list_bytes()), bound);
  EXPECT_GE(nl.list_bytes(), units * sizeof(std::uint16_t));
}

TEST(NeighbourLists, PairLoopsReadListsLongerThanTheirStackBuffer) {
  // The pair loops decode a list on the stack (1,024 entries) and lists longer than that in a
  // per-thread buffer. A wide support (h = 3.5 dx, about 1,400 neighbours inside the block) takes the
  // long path. The plain velocity gradient (eq. 3; not the corrected one, which is exact for a linear
  // field with any subset of the neighbours) must equal a brute-force sum over all particles.
  const int side = 16;
  const double dx = 1.0, h = 3.5;
  std::vector<double> x, v;
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        const double jitter = 0.1 * std::sin(1.7 * (i + 3 * j + 7 * k));
        const double p[3] = {i * dx + jitter, j * dx - jitter, k * dx + 0.5 * jitter};
        x.insert(x.end(), p, p + 3);
        // A velocity field with a different value at every particle.
        v.insert(v.end(), {std::sin(0.3 * p[0] + 0.1 * p[2]), std::cos(0.2 * p[1]), 0.01 * p[0] * p[1]});
      }
  const std::size_t n = x.size() / 3;
  NeighbourList nl;
  nl.build(x.data(), n, kernel_support_radius(h));
  std::size_t longest = 0;
  for (std::size_t i = 0; i < n; ++i) longest = std::max(longest, nl.size(i));
  ASSERT_GT(longest, 1024u);  // the long path is taken
  const std::vector<double> volume(n, dx * dx * dx);
  std::vector<double> L(9 * n);
  velocity_gradient(nl, KernelKind::CubicSpline, h, x.data(), v.data(), volume.data(), false, L.data(), nullptr,
                    nullptr, n);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (nl.size(i) <= 1024) continue;
    double ref[9] = {}, bound[9] = {};
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double d[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
      const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double f = volume[j] * kernel_gradient_factor(KernelKind::CubicSpline, r, h);
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const double t = (v[3 * j + a] - v[3 * i + a]) * f * d[b];
          ref[3 * a + b] += t;
          bound[3 * a + b] += std::abs(t);
        }
    }
    // The two sums differ only in their order (cell order against index order): round-off of at
    // most ~n_terms * 1.1e-16 of the sum of the terms' magnitudes (1,500 terms: 1.7e-13); 1e-12 of it
    // leaves a factor 6 and is far below a typical single term (~1e-3 of the sum).
    for (int c = 0; c < 9; ++c)
      EXPECT_NEAR(L[9 * i + c], ref[c], 1e-12 * bound[c]) << "particle " << i << " component " << c;
    ++checked;
  }
  EXPECT_GT(checked, 100u);
}

// The build may take its 20 bytes per point of scratch from a buffer the caller lends (the pass
// scratch, idle during a build: engine/simulation.cpp): the lists are then the same, entry for
// entry, and the list holds no build scratch of its own; a buffer too small is not used.
TEST(NeighbourLists, BorrowedBuildScratchGivesTheSameListsAndHoldsNone) {
  std::size_t n = 0;
  const std::vector<double> x = lattice(n);
  const double radius = 2.6;
  NeighbourList own, lent, small;
  own.rebuild(x.data(), n, radius, 0.2 * 1.3);
  const std::size_t doubles = (n * NeighbourList::build_scratch_bytes_per_point() + 7) / 8;
  std::vector<double> borrowed(doubles, 0.0), too_small(doubles - 1, 0.0);
  lent.rebuild(x.data(), n, radius, 0.2 * 1.3, SIZE_MAX, borrowed);
  small.rebuild(x.data(), n, radius, 0.2 * 1.3, SIZE_MAX, too_small);
  ASSERT_EQ(lent.count(), n);
  ASSERT_EQ(lent.pairs(), own.pairs());
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::uint32_t> a(own.size(i)), b(lent.size(i)), c(small.size(i));
    own.decode(i, a.data());
    lent.decode(i, b.data());
    small.decode(i, c.data());
    ASSERT_EQ(a, b) << i;
    ASSERT_EQ(a, c) << i;
  }
  // Only the cell starts (one per cell) are the list's own; the per-point arrays were lent.
  EXPECT_EQ(lent.build_scratch_bytes() + n * NeighbourList::build_scratch_bytes_per_point(), own.build_scratch_bytes());
  EXPECT_EQ(small.build_scratch_bytes(), own.build_scratch_bytes());
}

// The watch positions are kept in single precision (theory section 7). Far from the origin their
// rounding is a sizeable part of the skin: points near x = 3000 (float spacing 2.4e-4 there) with a
// skin of 0.01 (skin/2 = 5e-3). The rebuild test must stay conservative: whenever some point has
// moved more than skin/2 since the build (measured in double precision), needs_rebuild() is true;
// and when it is false, every pair closer than the radius at the new positions is in the lists.
// Moves of length 5e-3 +- 5e-4 in random directions put many points on either side of skin/2.
TEST(NeighbourLists, SinglePrecisionWatchPositionsNeverMissARebuild) {
  const std::size_t n = 400;
  const double radius = 1.0, skin = 0.01;
  std::vector<double> x0(3 * n);
  std::uint64_t state = 12345;
  auto uniform = [&state] {  // a small LCG: deterministic, no library distribution differences
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1p-53;
  };
  for (std::size_t k = 0; k < 3 * n; ++k) x0[k] = 3000.0 + 6.0 * uniform();
  NeighbourList nl;
  nl.rebuild(x0.data(), n, radius, skin);
  EXPECT_FALSE(nl.needs_rebuild(x0.data(), n, radius, skin));
  int rebuilds_required = 0, quiet = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<double> x = x0;
    // One point moves by a length near skin/2, the others by less than skin/4.
    const std::size_t moved = static_cast<std::size_t>(uniform() * n) % n;
    bool beyond = false;
    for (std::size_t i = 0; i < n; ++i) {
      double d[3], len2 = 0.0;
      for (int c = 0; c < 3; ++c) {
        d[c] = uniform() - 0.5;
        len2 += d[c] * d[c];
      }
      const double length = i == moved ? 5e-3 + 1e-3 * (uniform() - 0.5) : 2.5e-3 * uniform();
      double shift2 = 0.0;
      for (int c = 0; c < 3; ++c) {
        x[3 * i + c] += length * d[c] / std::sqrt(len2);
        const double s = x[3 * i + c] - x0[3 * i + c];
        shift2 += s * s;
      }
      beyond = beyond || shift2 > 0.25 * skin * skin;
    }
    const bool rebuild = nl.needs_rebuild(x.data(), n, radius, skin);
    if (beyond) {
      ++rebuilds_required;
      EXPECT_TRUE(rebuild) << "trial " << trial;
    }
    if (!rebuild) {
      ++quiet;
      for (std::size_t i = 0; i < n; ++i) {
        std::vector<std::uint32_t> listed;
        nl.for_each(i, [&](std::size_t j) { listed.push_back(static_cast<std::uint32_t>(j)); });
        for (std::size_t j = 0; j < n; ++j)
          if (j != i && distance(x, i, j) < radius)
            ASSERT_NE(std::find(listed.begin(), listed.end(), j), listed.end()) << i << " " << j;
      }
    }
  }
  // Both branches were exercised (the moves straddle skin/2).
  EXPECT_GT(rebuilds_required, 50);
  EXPECT_GT(quiet, 50);
}
