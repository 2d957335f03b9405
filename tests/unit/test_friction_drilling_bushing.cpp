// The friction-drilling bushing counts only sheet material joined to the clamped rim (docs/theory.md
// eqs. 127-129 and 127a; plugins/processes/friction_drilling/sheet_connectivity.hpp), tested on
// synthetic particle sets built like the plugin's sheet (cell-centred lattice clipped to a disc, the
// rim ring clamped): material moved below the sheet is not a bushing, a chain of neighbours is, the
// chain may pass through the cut planes of a sector, and the core's bond rule cuts links.
//
// Tolerances: the heights are differences of lattice coordinates, exact up to the round-off of a
// few additions of dx (1e-12 m absolute); counts are exact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "processes/friction_drilling/sheet_connectivity.hpp"

namespace {

using sphforge::friction_drilling::band_extremes;
using sphforge::friction_drilling::BandExtremes;
using sphforge::friction_drilling::SheetConnectivity;
using sphforge::friction_drilling::SheetParticles;

constexpr double kDx = 0.2e-3;              // particle spacing, m
constexpr double kRadius = 3.0e-3;          // disc radius, m
constexpr double kClampWidth = 0.5e-3;      // clamped rim, m
constexpr int kLayers = 3;                  // sheet thickness 3 dx, lower surface z = 0
constexpr double kBandInner = 1.0e-3, kBandOuter = 2.0e-3;
constexpr std::size_t kRank = 3;
constexpr double kLink = 1.5 * kDx;         // the plugin's default link distance
constexpr double kTol = 1e-12;

/// A sheet with its fields, as the process sees it through the core's arrays.
struct Sheet {
  std::vector<double> x, failed, pressure, S;
  std::vector<std::int64_t> clamped;
  bool with_failure = false;

  std::size_t size() const { return clamped.size(); }

  /// The plugin's lattice (eq. 121): sites ((i + 1/2) dx, (j + 1/2) dx, (k + 1/2) dx) in the disc;
  /// `quadrant`: only the 90 deg sector x > 0, y > 0 (what the core keeps of a sector run).
  static Sheet disc(bool quadrant) {
    Sheet s;
    const int nr = static_cast<int>(std::ceil(kRadius / kDx)) + 1;
    for (int k = 0; k < kLayers; ++k)
      for (int j = -nr; j < nr; ++j)
        for (int i = -nr; i < nr; ++i) {
          const double x = (i + 0.5) * kDx, y = (j + 0.5) * kDx;
          if (quadrant && (x < 0.0 || y < 0.0)) continue;
          if (std::hypot(x, y) <= kRadius - 0.5 * kDx + 1e-9 * kDx) s.add(x, y, (k + 0.5) * kDx);
        }
    return s;
  }

  std::size_t add(double x, double y, double z) {
    this->x.insert(this->x.end(), {x, y, z});
    clamped.push_back(std::hypot(x, y) >= kRadius - kClampWidth ? 1 : 0);
    failed.push_back(0.0);
    pressure.push_back(0.0);
    S.insert(S.end(), 6, 0.0);
    return clamped.size() - 1;
  }

  /// Index of the particle at (x, y, z) (to a tenth of dx); fails the test when there is none.
  std::size_t at(double x, double y, double z) const {
    for (std::size_t i = 0; i < size(); ++i)
      if (std::abs(this->x[3 * i] - x) < 0.1 * kDx && std::abs(this->x[3 * i + 1] - y) < 0.1 * kDx &&
          std::abs(this->x[3 * i + 2] - z) < 0.1 * kDx)
        return i;
    ADD_FAILURE() << "no particle at " << x << ", " << y << ", " << z;
    return 0;
  }

  SheetParticles view() const {
    SheetParticles p;
    p.count = size();
    p.position = x.data();
    p.seed = clamped.data();
    if (with_failure) {
      p.failed = failed.data();
      p.pressure = pressure.data();
      p.deviatoric_stress = S.data();
    }
    return p;
  }
};

/// Lower bushing height h_low = max(0, z_bottom - (z_lo - dx/2)) (eq. 128), z_bottom = 0.
double lower_height(const BandExtremes& e) { return e.found ? std::max(0.0, -(e.z_low - 0.5 * kDx)) : 0.0; }

struct Bushing {
  BandExtremes with, without;  // with the connectivity test (eq. 127a) and without (the old rule)
  std::size_t connected = 0;
};

Bushing measure(const Sheet& s, SheetConnectivity& c, int sectors) {
  std::vector<double> hi, lo;
  Bushing b;
  b.connected = c.compute(s.view(), kLink, sectors);
  b.with = band_extremes(s.view(), &c, kBandInner, kBandOuter, kRank, hi, lo);
  b.without = band_extremes(s.view(), nullptr, kBandInner, kBandOuter, kRank, hi, lo);
  return b;
}

TEST(FrictionDrillingBushing, IntactSheetIsConnectedAndHasNoBushing) {
  const Sheet s = Sheet::disc(false);
  SheetConnectivity c;
  const Bushing b = measure(s, c, 1);
  EXPECT_EQ(b.connected, s.size());
  EXPECT_EQ(b.with.detached, 0u);
  ASSERT_TRUE(b.with.found);
  EXPECT_NEAR(lower_height(b.with), 0.0, kTol);
  EXPECT_NEAR(b.with.z_high, (kLayers - 0.5) * kDx, kTol);
}

// (a) A cluster of four band particles moved 5 dx below the sheet (joined to each other, not to the
// sheet): the old rule takes its 3rd lowest as the bushing, the connectivity test ignores it.
TEST(FrictionDrillingBushing, ClusterBelowTheSheetIsNotABushing) {
  Sheet s = Sheet::disc(false);
  const double y = 0.5 * kDx, z = 0.5 * kDx - 5.0 * kDx;  // 5 dx below the lowest layer
  for (int m = 0; m < 4; ++m) {
    const std::size_t i = s.at((7.5 + m) * kDx, y, 0.5 * kDx);  // r = 1.5 .. 2.1 mm: three in the band
    s.x[3 * i + 2] = z;
  }
  SheetConnectivity c;
  const Bushing b = measure(s, c, 1);
  EXPECT_EQ(b.connected, s.size() - 4);
  EXPECT_EQ(b.with.detached, 3u);  // the fourth (r = 2.1 mm) lies outside the band
  // The old rule: the 3rd lowest particle of the band is in the cluster, h_low = 5 dx.
  EXPECT_NEAR(lower_height(b.without), 5.0 * kDx, kTol);
  // The connectivity test: only the sheet, whose lowest layer has h_low = 0.
  EXPECT_NEAR(lower_height(b.with), 0.0, kTol);
  EXPECT_GT(lower_height(b.without) - lower_height(b.with), 4.9 * kDx);
}

// A single particle far below (a torn-off droplet): also ignored; with rank 1 the old rule would
// have read it as a 10 mm bushing.
TEST(FrictionDrillingBushing, SingleParticleFarBelowIsIgnored) {
  Sheet s = Sheet::disc(false);
  const std::size_t i = s.at(7.5 * kDx, 0.5 * kDx, 0.5 * kDx);
  s.x[3 * i + 2] = -10e-3;
  SheetConnectivity c;
  std::vector<double> hi, lo;
  EXPECT_EQ(c.compute(s.view(), kLink, 1), s.size() - 1);
  EXPECT_FALSE(c.connected(i));
  const BandExtremes old_rule = band_extremes(s.view(), nullptr, kBandInner, kBandOuter, 1, hi, lo);
  const BandExtremes joined = band_extremes(s.view(), &c, kBandInner, kBandOuter, 1, hi, lo);
  EXPECT_NEAR(lower_height(old_rule), 10e-3 + 0.5 * kDx, kTol);
  EXPECT_NEAR(lower_height(joined), 0.0, kTol);
  EXPECT_EQ(joined.detached, 1u);
}

// (b) A column of particles spaced dx hanging from the lowest layer is joined through the chain and
// counted; the same column with one missing particle (a 2 dx gap, beyond the 1.5 dx link) is not.
TEST(FrictionDrillingBushing, HangingColumnIsCountedUnlessAParticleIsMissing) {
  const double x0 = 7.5 * kDx, y0 = 0.5 * kDx;  // r = 1.5 mm, in the band
  for (const bool gap : {false, true}) {
    Sheet s = Sheet::disc(false);
    std::vector<std::size_t> column;
    for (int k = 1; k <= 6; ++k)
      if (!(gap && k == 1)) column.push_back(s.add(x0, y0, 0.5 * kDx - k * kDx));
    SheetConnectivity c;
    const Bushing b = measure(s, c, 1);
    // The old rule counts the column either way: its 3rd lowest particle is k = 4, h_low = 4 dx.
    EXPECT_NEAR(lower_height(b.without), 4.0 * kDx, kTol) << "gap " << gap;
    if (!gap) {
      EXPECT_EQ(b.connected, s.size());
      EXPECT_EQ(b.with.detached, 0u);
      EXPECT_NEAR(lower_height(b.with), 4.0 * kDx, kTol);
    } else {
      for (std::size_t i : column) EXPECT_FALSE(c.connected(i));
      EXPECT_EQ(b.with.detached, column.size());
      EXPECT_NEAR(lower_height(b.with), 0.0, kTol);
    }
  }
}

// A diagonal chain (neighbours sqrt(2) dx apart, in x-z) is joined: 1.5 dx includes the lattice's
// second neighbours, which a sheared or drawn bushing wall consists of.
TEST(FrictionDrillingBushing, DiagonalChainIsCounted) {
  Sheet s = Sheet::disc(false);
  std::vector<std::size_t> chain;
  // r = 1.3 .. 1.9 mm, all in the band; only k = 1 touches the sheet (dx below its lowest layer).
  for (int k = 1; k <= 4; ++k) chain.push_back(s.add((5.5 + k) * kDx, 0.5 * kDx, 0.5 * kDx - k * kDx));
  SheetConnectivity c;
  const Bushing b = measure(s, c, 1);
  for (std::size_t i : chain) EXPECT_TRUE(c.connected(i));
  EXPECT_EQ(b.with.detached, 0u);
  EXPECT_NEAR(lower_height(b.with), 2.0 * kDx, kTol);  // 3rd lowest: k = 2 at z = -1.5 dx
  // The same chain without k = 2 (a gap of 2 sqrt(2) dx): k = 3 and 4 fall off.
  Sheet sparse = Sheet::disc(false);
  std::vector<std::size_t> loose;
  for (int k = 1; k <= 4; ++k) {
    if (k == 2) continue;
    const std::size_t i = sparse.add((5.5 + k) * kDx, 0.5 * kDx, 0.5 * kDx - k * kDx);
    if (k > 2) loose.push_back(i);
  }
  SheetConnectivity c2;
  c2.compute(sparse.view(), kLink, 1);
  for (std::size_t i : loose) EXPECT_FALSE(c2.connected(i));
}

// The core's bond rule (eqs. 111-112): the column hangs from the sheet's lowest layer, whose
// particles and the column's first share a failure state and an axial stress S_zz. Under tension
// along z the first particle's bonds to the layer (straight down and the sqrt(2) dx diagonals) are
// broken and the column is detached; under compression, or with only one side failed, it stays
// joined. The layer's own links (horizontal, no normal stress) and those to the intact layer above
// keep the sheet whole.
TEST(FrictionDrillingBushing, BrokenBondUnderTensionDetaches) {
  const double x0 = 7.5 * kDx, y0 = 0.5 * kDx;
  struct Variant {
    double failed_top, failed_first, szz;  // failed flags of the pair and its axial stress S_zz (p = 0)
    bool joined;
  };
  for (const Variant v : {Variant{1.0, 1.0, 100e6, false}, Variant{1.0, 1.0, -100e6, true},
                          Variant{1.0, 0.0, 100e6, true}, Variant{0.0, 0.0, 100e6, true}}) {
    Sheet s = Sheet::disc(false);
    s.with_failure = true;
    const std::size_t sheet_size = s.size();
    std::vector<std::size_t> column;
    for (int k = 1; k <= 4; ++k) column.push_back(s.add(x0, y0, 0.5 * kDx - k * kDx));
    for (std::size_t i = 0; i < sheet_size; ++i)
      if (s.x[3 * i + 2] < kDx) {  // the lowest layer
        s.failed[i] = v.failed_top;
        s.S[6 * i + 2] = v.szz;
      }
    s.failed[column[0]] = v.failed_first;
    s.S[6 * column[0] + 2] = v.szz;
    SheetConnectivity c;
    const Bushing b = measure(s, c, 1);
    for (std::size_t i : column) EXPECT_EQ(c.connected(i), v.joined) << v.failed_top << v.failed_first << v.szz;
    EXPECT_EQ(b.connected, v.joined ? s.size() : sheet_size);
    EXPECT_NEAR(lower_height(b.with), v.joined ? 2.0 * kDx : 0.0, kTol);
  }
}

// Pressure counts as well: sigma = S - p I, so a negative pressure (hydrostatic tension) breaks the
// bonds of two failed particles and a positive one keeps them (the lowest layer and the hanging
// particle failed; the layer stays joined through the intact layer above).
TEST(FrictionDrillingBushing, PressureEntersTheBondRule) {
  const double x0 = 7.5 * kDx, y0 = 0.5 * kDx;
  for (const double p : {-50e6, 50e6}) {
    Sheet s = Sheet::disc(false);
    s.with_failure = true;
    const std::size_t hanging = s.add(x0, y0, -0.5 * kDx);
    for (std::size_t i = 0; i < s.size(); ++i)
      if (s.x[3 * i + 2] < kDx) {
        s.failed[i] = 1.0;
        s.pressure[i] = p;
      }
    SheetConnectivity c;
    EXPECT_EQ(c.compute(s.view(), kLink, 1), p > 0.0 ? s.size() : s.size() - 1) << "p = " << p;
    EXPECT_EQ(c.connected(hanging), p > 0.0) << "p = " << p;
  }
}

/// (c) A 90 deg sector (x > 0, y > 0) with a column hanging 5 dx below the sheet next to one cut
/// plane and a particle P next to the other cut plane, level with the column's foot and dx from
/// the column foot's rotated image. P touches nothing in the sector itself: only the chain through
/// the cut plane joins it. `swap`: the column at the plane y = 0 and P at x = 0 (the other rotation).
struct SectorChain {
  Sheet s = Sheet::disc(true);
  std::size_t foot = 0, p = 0;
  std::vector<std::size_t> column;
  explicit SectorChain(bool swap) {
    const double a = 0.5 * kDx, b = 7.5 * kDx;  // column at (a, b), next to the plane x = 0
    const double z_foot = 0.5 * kDx - 5.0 * kDx;
    for (int k = 1; k <= 5; ++k) {
      column.push_back(swap ? s.add(b, a, 0.5 * kDx - k * kDx) : s.add(a, b, 0.5 * kDx - k * kDx));
      foot = column.back();
    }
    // The foot's image by -90 deg (x, y) -> (y, -x) is (b, -a); P at (b, +a) is dx from it (for
    // swap, the image by +90 deg (x, y) -> (-y, x) of (b, a) is (-a, b); P at (a, b)).
    p = swap ? s.add(a, b, z_foot) : s.add(b, a, z_foot);
  }
};

TEST(FrictionDrillingBushing, SectorChainThroughTheCutPlaneIsConnected) {
  for (const bool swap : {false, true}) {
    SectorChain chain(swap);
    SheetConnectivity c;
    // Without images (as if the quadrant were the whole body) P is alone.
    c.compute(chain.s.view(), kLink, 1);
    EXPECT_TRUE(c.connected(chain.foot)) << "swap " << swap;
    EXPECT_FALSE(c.connected(chain.p)) << "swap " << swap;
    // A 90 deg sector (N = 4): P is joined through the cut plane.
    EXPECT_EQ(c.compute(chain.s.view(), kLink, 4), chain.s.size()) << "swap " << swap;
    EXPECT_TRUE(c.connected(chain.p)) << "swap " << swap;
    // ... and it counts for the bushing: three particles at the column's lowest levels
    // (foot and P at -4.5 dx, the next at -3.5 dx): h_low = 4 dx.
    std::vector<double> hi, lo;
    const BandExtremes e = band_extremes(chain.s.view(), &c, kBandInner, kBandOuter, kRank, hi, lo);
    EXPECT_EQ(e.detached, 0u);
    EXPECT_NEAR(lower_height(e), 4.0 * kDx, kTol) << "swap " << swap;
  }
}

// The image carries its stress rotated with it (Q sigma Q^T): the links through the cut run along y
// (swap false: P at (b, a), the foot's image at (b, -a), the next one's at (b, -a, +dx)). A failed
// column with sigma_xx > 0 has sigma_yy > 0 in its image: tension along the links, broken. With
// sigma_yy > 0 the image has sigma_xx > 0, across the links: no tension, joined. Without the
// rotation both answers flip. (The column's own links are vertical: no normal stress, intact.)
TEST(FrictionDrillingBushing, SectorImageStressIsRotated) {
  for (const int component : {0, 1}) {  // S_xx or S_yy of the column
    SectorChain chain(false);
    chain.s.with_failure = true;
    chain.s.failed[chain.p] = 1.0;
    for (std::size_t i : chain.column) {
      chain.s.failed[i] = 1.0;
      chain.s.S[6 * i + component] = 100e6;
    }
    SheetConnectivity c;
    c.compute(chain.s.view(), kLink, 4);
    EXPECT_EQ(c.connected(chain.p), component == 1) << "component " << component;
  }
}

// A half disc (N = 2): one image (180 deg), and a chain through the cut is found as well.
TEST(FrictionDrillingBushing, HalfDiscChainThroughTheCut) {
  Sheet s;
  {
    const Sheet full = Sheet::disc(false);
    for (std::size_t i = 0; i < full.size(); ++i)
      if (full.x[3 * i + 1] > 0.0) s.add(full.x[3 * i], full.x[3 * i + 1], full.x[3 * i + 2]);
  }
  // Column at (b, a) next to the cut y = 0; its foot's image by 180 deg is (-b, -a); P at (-b, a).
  const double a = 0.5 * kDx, b = 7.5 * kDx;
  for (int k = 1; k <= 5; ++k) s.add(b, a, 0.5 * kDx - k * kDx);
  const std::size_t p = s.add(-b, a, 0.5 * kDx - 5.0 * kDx);
  SheetConnectivity c;
  c.compute(s.view(), kLink, 1);
  EXPECT_FALSE(c.connected(p));
  EXPECT_EQ(c.compute(s.view(), kLink, 2), s.size());
  EXPECT_TRUE(c.connected(p));
}

// The arrays are reused: a second call on a smaller set gives the answer of a fresh object.
TEST(FrictionDrillingBushing, RepeatedCallsReuseStorage) {
  Sheet big = Sheet::disc(false);
  big.add(7.5 * kDx, 0.5 * kDx, -10e-3);
  const SectorChain small(false);
  SheetConnectivity reused, fresh;
  reused.compute(big.view(), kLink, 1);
  EXPECT_EQ(reused.compute(small.s.view(), kLink, 4), fresh.compute(small.s.view(), kLink, 4));
  for (std::size_t i = 0; i < small.s.size(); ++i) EXPECT_EQ(reused.connected(i), fresh.connected(i));
}

}  // namespace
