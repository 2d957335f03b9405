// The artificial stress (eq. 9) is computed in place in the step (engine/simulation.cpp): R
// overwrites sigma/rho^2, which saves six doubles per particle of scratch. In place and out of
// place must agree bit for bit (each particle's inputs are read before its outputs are written).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>

#include "engine/neighbours.hpp"
#include "engine/sph_operators.hpp"
#include "sphforge/kernels.hpp"

using namespace sphforge;

TEST(ArtificialStress, InPlaceEqualsSeparateOutputBitForBit) {
  const std::size_t n = 2000;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> p(n), S(6 * n), rho(n);
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = 1e6 * u(rng);
    for (int c = 0; c < 6; ++c) S[6 * i + c] = 1e6 * u(rng);
    rho[i] = 2700.0 * (1.0 + 0.1 * u(rng));
  }
  std::vector<double> t(6 * n), separate(6 * n);
  stress_over_density_squared(p.data(), S.data(), rho.data(), t.data(), n);
  artificial_stress(t.data(), 0.3, separate.data(), n);
  std::vector<double> in_place = t;
  artificial_stress(in_place.data(), 0.3, in_place.data(), n);
  std::size_t nonzero = 0;
  for (std::size_t k = 0; k < 6 * n; ++k) {
    ASSERT_EQ(in_place[k], separate[k]) << "entry " << k;  // exact: the same operations on the same inputs
    nonzero += separate[k] != 0.0 ? 1 : 0;
  }
  EXPECT_GT(nonzero, n);  // random stresses have tensile principal values: the test compares real numbers
}

// Where Gershgorin's bound puts every eigenvalue of sigma/rho^2 at or below 0, artificial_stress()
// skips the eigen-decomposition and writes R = 0 (eq. 9). Against an independent evaluation here:
// R = -epsilon sum_k max(s_k, 0) e_k e_k^T from Eigen's iterative solver, on a mix of compressed
// particles (the skip), compressed-but-sheared ones whose bound is positive (the full path, R = 0
// too) and particles under tension.
TEST(ArtificialStress, GershgorinSkipMatchesTheEigenDecomposition) {
  const std::size_t n = 3000;
  const double epsilon = 0.3;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> t(6 * n), R(6 * n, 7.0);  // 7: R is overwritten everywhere
  std::size_t skipped = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double p = i % 3 == 0 ? 5.0 : (i % 3 == 1 ? 1.2 : -0.5);  // compression, near-zero margin, tension
    for (int c = 0; c < 3; ++c) t[6 * i + c] = -p + 0.3 * u(rng);
    for (int c = 3; c < 6; ++c) t[6 * i + c] = 0.5 * u(rng);
    const double* s = &t[6 * i];
    const double bound = std::max({s[0] + std::abs(s[3]) + std::abs(s[5]), s[1] + std::abs(s[3]) + std::abs(s[4]),
                                   s[2] + std::abs(s[4]) + std::abs(s[5])});
    skipped += bound <= 0.0 ? 1 : 0;
  }
  artificial_stress(t.data(), epsilon, R.data(), n);
  std::size_t zero_by_eigen = 0, tensile = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double* s = &t[6 * i];
    Eigen::Matrix3d m;
    m << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m);
    Eigen::Vector3d r_principal;
    for (int k = 0; k < 3; ++k) r_principal[k] = -epsilon * std::max(eig.eigenvalues()[k], 0.0);
    const Eigen::Matrix3d expected = eig.eigenvectors() * r_principal.asDiagonal() * eig.eigenvectors().transpose();
    const double got[6] = {R[6 * i], R[6 * i + 1], R[6 * i + 2], R[6 * i + 3], R[6 * i + 4], R[6 * i + 5]};
    const double want[6] = {expected(0, 0), expected(1, 1), expected(2, 2),
                            expected(0, 1), expected(1, 2), expected(0, 2)};
    if (r_principal.maxCoeff() == 0.0 && r_principal.minCoeff() == 0.0) {
      for (int c = 0; c < 6; ++c) ASSERT_EQ(got[c], 0.0) << "particle " << i << " entry " << c;
      zero_by_eigen += 1;
    } else {
      // 1e-12 of |sigma/rho^2| (order 1 here): two eigen-solvers (closed form in the engine,
      // iterative here) agree to round-off, not to the bit.
      for (int c = 0; c < 6; ++c) ASSERT_NEAR(got[c], want[c], 1e-12) << "particle " << i << " entry " << c;
      tensile += 1;
    }
  }
  // All three kinds occur, so each branch was compared.
  EXPECT_GT(skipped, n / 10);
  EXPECT_GT(zero_by_eigen, skipped);
  EXPECT_GT(tensile, n / 10);
}

namespace {
// A jittered 12^3 lattice with its neighbour lists, for the momentum pass.
struct MomentumBlock {
  std::size_t n = 0;
  double dx = 1e-3, h = 1.3e-3;
  std::vector<double> x, v, m, rho, volume, stress_c;
  NeighbourList nl;
  MomentumBlock() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int side = 12;
    for (int k = 0; k < side; ++k)
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
          x.insert(x.end(), {(i + 0.1 * u(rng)) * dx, (j + 0.1 * u(rng)) * dx, (k + 0.1 * u(rng)) * dx});
          v.insert(v.end(), {0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng)});  // some pairs approach: viscosity acts
        }
    n = x.size() / 3;
    m.assign(n, 2700.0 * dx * dx * dx);
    rho.resize(n);
    volume.resize(n);
    stress_c.resize(9 * n);
    for (std::size_t i = 0; i < n; ++i) {
      rho[i] = 2700.0 * (1.0 + 0.01 * u(rng));
      volume[i] = m[i] / rho[i];
      for (int c = 0; c < 9; ++c) stress_c[9 * i + c] = 1e7 * u(rng);
    }
    nl.build(x.data(), n, 2.1 * h);
  }
  std::vector<double> acceleration(const double* R) const {
    ArtificialStress as;
    as.w_dx = kernel_value(KernelKind::CubicSpline, dx, h);
    if (!R) as.epsilon = 0.0;
    std::vector<double> a(3 * n);
    // The tension bits as the step makes them, so that the sums without the term are exercised.
    std::vector<std::uint64_t> tension((n + 63) / 64);
    if (R) mark_tension(R, n, tension.data());
    momentum_rate(nl, KernelKind::CubicSpline, h, ArtificialViscosity{}, 5000.0, x.data(), v.data(), m.data(),
                  rho.data(), volume.data(), stress_c.data(), as, R, R ? tension.data() : nullptr, a.data(), n);
    return a;
  }
};
}  // namespace

// Where neither a particle nor any neighbour is under tension (R = 0), the momentum pass runs its loop
// without the artificial-stress terms: the accelerations must be those of the pass without artificial
// stress to the bit. Where one particle is under tension, exactly its neighbourhood must differ.
TEST(ArtificialStress, TensionFreeNeighbourhoodsGiveTheSumsWithoutItBitForBit) {
  const MomentumBlock b;
  const std::vector<double> without = b.acceleration(nullptr);
  std::vector<double> R(6 * b.n, 0.0);
  const std::vector<double> all_zero = b.acceleration(R.data());
  for (std::size_t k = 0; k < 3 * b.n; ++k) ASSERT_EQ(all_zero[k], without[k]) << "entry " << k;

  const std::size_t tense = b.n / 2 + 6;  // an interior particle
  R[6 * tense] = -2.0, R[6 * tense + 1] = -1.0, R[6 * tense + 3] = 0.5;
  const std::vector<double> one = b.acceleration(R.data());
  std::vector<bool> near(b.n, false);
  near[tense] = true;
  b.nl.for_each(tense, [&](std::size_t j) { near[j] = true; });
  std::size_t changed = 0, near_count = 0;
  for (std::size_t i = 0; i < b.n; ++i) {
    const bool same = one[3 * i] == without[3 * i] && one[3 * i + 1] == without[3 * i + 1] &&
                      one[3 * i + 2] == without[3 * i + 2];
    if (!near[i]) {
      EXPECT_TRUE(same) << "particle " << i << " has no neighbour under tension";
    } else {
      near_count += 1;
      changed += same ? 0 : 1;
    }
  }
  // Pairs in the 2.1 h list but beyond the 2 h support carry no term; all others do.
  EXPECT_GT(changed, near_count / 2);
}

// mark_tension() sets exactly the bits of the particles with R != 0, over a count that is not a
// multiple of 64 (the last word partly used, its high bits clear), and from the artificial
// stress's own output: particles in compression only get R = 0, those with a tensile principal
// stress a nonzero, negative semidefinite R, whose trace is then nonzero.
TEST(ArtificialStress, TensionBitsMarkExactlyTheParticlesWithNonzeroR) {
  const std::size_t n = 130;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> p(n), S(6 * n, 0.0), rho(n, 1000.0), R(6 * n);
  for (std::size_t i = 0; i < n; ++i) {
    // every third particle in tension (negative pressure), the others compressed with a small shear
    p[i] = i % 3 == 0 ? -1e6 * (1.0 + 0.5 * u(rng)) : 1e6 * (1.0 + 0.5 * u(rng));
    S[6 * i + 3] = 1e4 * u(rng);
  }
  stress_over_density_squared(p.data(), S.data(), rho.data(), R.data(), n);
  artificial_stress(R.data(), 0.3, R.data(), n);
  std::vector<std::uint64_t> bits(3, ~std::uint64_t{0});  // garbage in: every word must be written
  mark_tension(R.data(), n, bits.data());
  for (std::size_t i = 0; i < n; ++i) {
    bool nonzero = false;
    for (int c = 0; c < 6; ++c) nonzero = nonzero || R[6 * i + c] != 0.0;
    EXPECT_EQ(nonzero, i % 3 == 0) << "particle " << i;
    EXPECT_EQ((bits[i / 64] >> (i % 64)) & 1u, nonzero ? 1u : 0u) << "particle " << i;
  }
  EXPECT_EQ(bits[2] >> (n - 128), 0u) << "bits beyond the last particle";
}
