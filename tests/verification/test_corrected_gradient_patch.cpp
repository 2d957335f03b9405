// Verification (label `verification`): patch test of the corrected velocity gradient (theory
// eqs. 3-3b). On a 3D block of particles jittered randomly by up to 20 % of dx, a linear velocity
// field v = A x + b must come out as L = A at every particle where the correction was applied
// (gradient_condition != -1), surface and corner particles included: L_i M_i^-1 is exact for
// linear fields whatever the neighbourhood, because the sum defining L_i is then exactly A M_i.
//
// Tolerance 1e-10 relative to |A|: the only error left is round-off. The sums over ~100 neighbours
// carry relative errors of order 100 * 1e-16, and the 3x3 solve L M^-1 multiplies them by at most
// cond(M) < 50 (the correction falls back to the plain gradient beyond that), so the error stays
// below ~1e-12; 1e-10 leaves a margin of 100 without letting any discretisation error through
// (the uncorrected gradient misses by 1e-2 and more on the same particles, checked below).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "engine/neighbours.hpp"
#include "engine/sph_operators.hpp"

namespace {

using namespace sphforge;

struct JitteredBlock {
  std::size_t n = 0;
  double dx = 1e-3, h = 1.3e-3;
  std::vector<double> x, v, volume;
  std::vector<bool> surface;  // on the outermost lattice layer
  double A[3][3] = {{0.3, -1.2, 0.5}, {2.0, 0.7, -0.4}, {-0.9, 1.1, -1.5}};  // 1/s
  double b[3] = {0.01, -0.02, 0.005};                                        // m/s

  explicit JitteredBlock(int side, KernelKind kernel) {
    std::mt19937 rng(20240611);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (int k = 0; k < side; ++k)
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
          const int lattice[3] = {i, j, k};
          double p[3];
          for (int d = 0; d < 3; ++d) p[d] = (lattice[d] + jitter(rng)) * dx;
          x.insert(x.end(), p, p + 3);
          for (int a = 0; a < 3; ++a) v.push_back(A[a][0] * p[0] + A[a][1] * p[1] + A[a][2] * p[2] + b[a]);
          surface.push_back(i == 0 || j == 0 || k == 0 || i == side - 1 || j == side - 1 || k == side - 1);
        }
    n = x.size() / 3;
    volume.assign(n, dx * dx * dx);
    nl.build(x.data(), n, kernel_support_radius(h) + 0.2 * h);  // with a Verlet skin, as in a run
    this->kernel = kernel;
  }

  /// Largest |L_i - A| / |A| (Frobenius) over particles selected by `use`.
  template <typename Use>
  double max_error(const std::vector<double>& L, Use use) const {
    double norm_a = 0.0;
    for (auto& row : A)
      for (double c : row) norm_a += c * c;
    norm_a = std::sqrt(norm_a);
    double worst = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!use(i)) continue;
      double e = 0.0;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) e += std::pow(L[9 * i + 3 * a + c] - A[a][c], 2);
      worst = std::max(worst, std::sqrt(e) / norm_a);
    }
    return worst;
  }

  NeighbourList nl;
  KernelKind kernel;
};

void check_patch(KernelKind kernel) {
  const JitteredBlock block(12, kernel);
  std::vector<double> L(9 * block.n), condition(block.n);
  velocity_gradient(block.nl, kernel, block.h, block.x.data(), block.v.data(), block.volume.data(), true, L.data(),
                    condition.data(), nullptr, block.n);
  std::size_t corrected = 0, corrected_surface = 0;
  for (std::size_t i = 0; i < block.n; ++i)
    if (condition[i] != -1.0) {
      ++corrected;
      if (block.surface[i]) ++corrected_surface;
    }
  // The correction must apply almost everywhere, surfaces included, or the test would prove little.
  EXPECT_GT(corrected, block.n * 95 / 100);
  EXPECT_GT(corrected_surface, 500u);
  EXPECT_LT(block.max_error(L, [&](std::size_t i) { return condition[i] != -1.0; }), 1e-10);
  EXPECT_LT(block.max_error(L, [&](std::size_t i) { return condition[i] != -1.0 && block.surface[i]; }), 1e-10);

  // Without the correction the jittered, truncated surface neighbourhoods are far from exact:
  // the test can fail.
  std::vector<double> plain(9 * block.n);
  velocity_gradient(block.nl, kernel, block.h, block.x.data(), block.v.data(), block.volume.data(), false,
                    plain.data(), nullptr, nullptr, block.n);
  EXPECT_GT(block.max_error(plain, [&](std::size_t i) { return block.surface[i]; }), 1e-2);
}

TEST(CorrectedGradientPatch, LinearVelocityExactOnJitteredBlockCubicSpline) { check_patch(KernelKind::CubicSpline); }
TEST(CorrectedGradientPatch, LinearVelocityExactOnJitteredBlockWendlandC2) { check_patch(KernelKind::WendlandC2); }
// The same with the generic pair loops, which CPUs without AVX2 run, and with the AVX2 loops,
// which CPUs with AVX-512VL do not run by default (each cap selects at most what the CPU has).
TEST(CorrectedGradientPatch, LinearVelocityExactWithGenericPairLoops) {
  const PairLoopIsa previous = limit_pair_loop_isa(PairLoopIsa::generic);
  check_patch(KernelKind::CubicSpline);
  check_patch(KernelKind::WendlandC2);
  limit_pair_loop_isa(previous);
}
TEST(CorrectedGradientPatch, LinearVelocityExactWithAvx2PairLoops) {
  const PairLoopIsa previous = limit_pair_loop_isa(PairLoopIsa::avx2);
  check_patch(KernelKind::CubicSpline);
  check_patch(KernelKind::WendlandC2);
  limit_pair_loop_isa(previous);
}

}  // namespace
