// Verification (label `verification`): variable spacing (theory section 19, eqs. 138-140). A block
// graded from a fine lattice (s = dx/2) to a coarse one (s = dx) at a plane, each coarse cell tiled
// exactly by 8 fine ones, every particle with its own smoothing length h_i = 1.3 s_i and a pair using
// h_ij = (h_i + h_j) / 2:
//  - patch test: the corrected velocity gradient of a linear field is exact at every corrected
//    particle, across the spacing change as anywhere (eq. 3b does not depend on the neighbourhood);
//    tolerance 1e-10 of |A|, the round-off bound of the uniform patch test
//    (test_corrected_gradient_patch.cpp);
//  - uniform stress (the "no spurious forces at the spacing change beyond a stated bound"):
//    with one spacing the interior sums cancel by symmetry to round-off (checked, 1e-10); at the
//    spacing change they do not. Bound: the interior, the change included, may feel no more than the
//    interior of a uniform lattice whose particles were moved at random by up to 5 % of dx, measured in
//    the same test (a disorder any deforming run exceeds within its first per cent of strain). Measured
//    (|a| rho s / |sigma|, where a particle on a free face gets 0.6-1.4): cubic spline 0.065 against
//    0.074, Wendland C2 0.054 against 0.086. The pair's mean kernel instead of its mean h gives 0.125 and
//    0.158, the larger h 0.128 and 0.135: both fail the bound, which is why eq. 138 takes the mean h;
//  - momentum: the pair forces are antisymmetric with h_ij symmetric, so sum_i m_i a_i = 0 to round-off;
//  - conduction (eq. 20) of a linear temperature field: conservative across the change (the heat sums
//    to zero, 1e-12) and zero in a uniform interior (1e-10). In the graded interior it is not zero, and
//    this test sets no bound on it but prints it: |Q| / (V k |grad T| / s) = 0.150 (cubic spline) and
//    0.139 (Wendland C2), about what a uniform lattice moved at random by 10 % of dx gives (0.146 and
//    0.164; 5 %: 0.078 and 0.084; a free face: up to 0.9). Brookshaw's form is not consistent on an
//    irregular neighbourhood, and the spacing change is one (docs/theory.md section 19);
//  - the neighbour lists hold each pair within (S_i + S_j) / 2 + skin (S = 2h) and none beyond it (eq. 140).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "engine/heat_conduction.hpp"
#include "engine/neighbours.hpp"
#include "engine/sph_operators.hpp"
#include "sphforge/kernels.hpp"

namespace {

using namespace sphforge;

constexpr double kHOverDx = 1.3;

struct GradedBlock {
  // x in [0, 2 W): fine (s = dx / 2) below x = W, coarse (s = dx) above; y, z in [0, W).
  static constexpr double dx = 1e-3;
  int cells;  // coarse cells per W
  double W;
  std::size_t n = 0;
  std::vector<double> x, s, h, volume, mass, support;
  double h_max = kHOverDx * dx, skin = 0.2 * kHOverDx * dx;
  NeighbourList nl;

  GradedBlock(bool graded, int cells_per_side, double jitter = 0.0) : cells(cells_per_side), W(cells_per_side * dx) {
    std::mt19937 rng(20261206);
    std::uniform_real_distribution<double> shake(-jitter, jitter);
    for (int k = 0; k < cells; ++k)
      for (int j = 0; j < cells; ++j)
        for (int i = 0; i < 2 * cells; ++i) {
          const double c[3] = {(i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx};
          if (graded && c[0] < W) {
            for (int f = 0; f < 8; ++f)
              add(c[0] + ((f & 1) ? 0.25 : -0.25) * dx, c[1] + ((f & 2) ? 0.25 : -0.25) * dx,
                  c[2] + ((f & 4) ? 0.25 : -0.25) * dx, 0.5 * dx);
          } else {
            add(c[0] + shake(rng) * dx, c[1] + shake(rng) * dx, c[2] + shake(rng) * dx, dx);
          }
        }
    n = s.size();
    for (std::size_t i = 0; i < n; ++i) support.push_back(kernel_support_radius(h[i]));
    nl.rebuild(x.data(), n, kernel_support_radius(h_max), skin, SIZE_MAX, {}, graded ? support.data() : nullptr);
  }
  void add(double a, double b, double c, double spacing) {
    x.insert(x.end(), {a, b, c});
    s.push_back(spacing);
    h.push_back(kHOverDx * spacing);
    volume.push_back(spacing * spacing * spacing);
    mass.push_back(7800.0 * spacing * spacing * spacing);
  }
  /// Farther than two of the largest supports from every free face: an interior particle, whose
  /// neighbours all have full support too (their C_j, eq. 3b, are those of the unbounded lattice).
  bool interior(std::size_t i) const {
    const double m = 2.0 * kernel_support_radius(h_max) + 1e-9;
    const double lo[3] = {0, 0, 0}, hi[3] = {2 * W, W, W};
    for (int d = 0; d < 3; ++d)
      if (x[3 * i + d] - lo[d] < m || hi[d] - x[3 * i + d] < m) return false;
    return true;
  }
};

TEST(VariableSpacing, ListsHoldThePairsWithinTheirOwnSupportPlusSkin) {
  const GradedBlock b(true, 6);
  std::size_t missing = 0, extra = 0;
  std::vector<char> listed(b.n);
  for (std::size_t i = 0; i < b.n; ++i) {
    std::fill(listed.begin(), listed.end(), 0);
    b.nl.for_each(i, [&](std::size_t j) { listed[j] = 1; });
    for (std::size_t j = 0; j < b.n; ++j) {
      if (j == i) continue;
      const double r = std::sqrt(std::pow(b.x[3 * i] - b.x[3 * j], 2) + std::pow(b.x[3 * i + 1] - b.x[3 * j + 1], 2) +
                                 std::pow(b.x[3 * i + 2] - b.x[3 * j + 2], 2));
      const double reach = 0.5 * (b.support[i] + b.support[j]) + b.skin;
      if (r < reach * (1 - 1e-6) && !listed[j]) ++missing;
      if (r > reach * (1 + 1e-4) && listed[j]) ++extra;
    }
  }
  EXPECT_EQ(missing, 0u);
  EXPECT_EQ(extra, 0u);
}

struct Residuals {
  double interior = 0.0;        // largest |a| rho s / |sigma| away from the free faces
  double face_min = 1e300, face_max = 0.0;  // the same on the free faces (not edges), the yardstick
  double patch = 0.0;           // largest |L - A| / |A| over the corrected particles
  double net_momentum = 0.0;    // |sum m a| / sum m |a|
  std::size_t corrected = 0, n = 0;
};

// The block under a uniform stress sigma = S - p I (with shear), and the patch test on it.
Residuals residuals(KernelKind kernel, bool graded, double jitter) {
  const GradedBlock b(graded, 14, jitter);
  Residuals out;
  out.n = b.n;
  const double A[3][3] = {{0.3, -1.2, 0.5}, {2.0, 0.7, -0.4}, {-0.9, 1.1, -1.5}};
  std::vector<double> v(3 * b.n);
  for (std::size_t i = 0; i < b.n; ++i)
    for (int a = 0; a < 3; ++a)
      v[3 * i + a] = A[a][0] * b.x[3 * i] + A[a][1] * b.x[3 * i + 1] + A[a][2] * b.x[3 * i + 2] + 0.01 * a;
  std::vector<double> L(9 * b.n), condition(b.n), C(6 * b.n);
  const double* hp = graded ? b.h.data() : nullptr;
  velocity_gradient(b.nl, kernel, b.h_max, b.x.data(), v.data(), b.volume.data(), true, L.data(), condition.data(),
                    C.data(), b.n, {}, hp);
  double norm_a = 0.0;
  for (auto& row : A)
    for (double c : row) norm_a += c * c;
  norm_a = std::sqrt(norm_a);
  for (std::size_t i = 0; i < b.n; ++i) {
    if (condition[i] < 0) continue;
    ++out.corrected;
    double e = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) e += std::pow(L[9 * i + 3 * a + c] - A[a][c], 2);
    out.patch = std::max(out.patch, std::sqrt(e) / norm_a);
  }

  const double p = 1e8, S6[6] = {2e7, -1e7, -1e7, 3e7, -2e7, 1e7};
  std::vector<double> pressure(b.n, p), S(6 * b.n), rho(b.n, 7800.0), stress_c(9 * b.n), acc(3 * b.n, 0.0);
  for (std::size_t i = 0; i < b.n; ++i)
    for (int c = 0; c < 6; ++c) S[6 * i + c] = S6[c];
  corrected_stress(pressure.data(), S.data(), C.data(), true, stress_c.data(), b.n);
  ArtificialViscosity av;
  ArtificialStress as;
  as.epsilon = 0.0;
  const std::vector<double> at_rest(3 * b.n, 0.0);
  momentum_rate(b.nl, kernel, b.h_max, av, 5000.0, b.x.data(), at_rest.data(), b.mass.data(), rho.data(),
                b.volume.data(), stress_c.data(), as, nullptr, nullptr, acc.data(), b.n, {}, hp);
  const double sigma_norm = std::sqrt(std::pow(S6[0] - p, 2) + std::pow(S6[1] - p, 2) + std::pow(S6[2] - p, 2) +
                                      2 * (S6[3] * S6[3] + S6[4] * S6[4] + S6[5] * S6[5]));
  double momentum[3] = {0, 0, 0}, momentum_scale = 0.0;
  const double hi[3] = {2 * b.W, b.W, b.W};
  for (std::size_t i = 0; i < b.n; ++i) {
    const double a = std::sqrt(acc[3 * i] * acc[3 * i] + acc[3 * i + 1] * acc[3 * i + 1] + acc[3 * i + 2] * acc[3 * i + 2]);
    const double rel = a * rho[i] * b.s[i] / sigma_norm;
    if (b.interior(i)) {
      out.interior = std::max(out.interior, rel);
    } else {
      int on = 0;  // faces this particle lies on (one layer deep)
      for (int d = 0; d < 3; ++d) on += (b.x[3 * i + d] < 0.6 * b.s[i]) + (hi[d] - b.x[3 * i + d] < 0.6 * b.s[i]);
      if (on == 1) out.face_min = std::min(out.face_min, rel), out.face_max = std::max(out.face_max, rel);
    }
    for (int d = 0; d < 3; ++d) momentum[d] += b.mass[i] * acc[3 * i + d];
    momentum_scale += b.mass[i] * a;
  }
  out.net_momentum =
      std::sqrt(momentum[0] * momentum[0] + momentum[1] * momentum[1] + momentum[2] * momentum[2]) / momentum_scale;
  return out;
}

void check_graded(KernelKind kernel) {
  const char* name = kernel == KernelKind::CubicSpline ? "cubic spline" : "Wendland C2";
  const Residuals uniform = residuals(kernel, false, 0.0);
  const Residuals graded = residuals(kernel, true, 0.0);
  const Residuals disordered = residuals(kernel, false, 0.05);
  for (const Residuals* r : {&uniform, &graded, &disordered}) {
    EXPECT_GT(r->corrected, r->n * 9 / 10);
    EXPECT_LT(r->patch, 1e-10);          // round-off (see the header)
    EXPECT_LT(r->net_momentum, 1e-12);   // antisymmetric pair forces
    EXPECT_GT(r->face_min, 0.3);         // the yardstick is of order one, as the header says
    EXPECT_LT(r->face_max, 2.0);
  }
  EXPECT_LT(uniform.interior, 1e-10);  // one spacing: the interior cancels to round-off
  // The bound: the spacing change may not disturb the interior more than a uniform lattice whose
  // particles are moved at random by up to 5 % of dx.
  EXPECT_LT(graded.interior, disordered.interior);
  std::printf("%s: interior |a| rho s / |sigma|: uniform %.1e, graded %.4f, uniform with 5 %% disorder %.4f; "
              "free faces %.2f .. %.2f; patch %.1e; net momentum %.1e\n",
              name, uniform.interior, graded.interior, disordered.interior, graded.face_min, graded.face_max,
              graded.patch, graded.net_momentum);
}

// Conduction (eq. 20) of a linear temperature field T = g . x: its Laplacian is zero, so the interior
// gets no heat; |Q_i| / (V_i k |g| / s_i) there, against a free face's (of order one), and the heat
// summed over the block (zero: the pair terms are antisymmetric).
struct HeatResiduals {
  double interior = 0.0, face_max = 0.0, net = 0.0;
};

HeatResiduals heat_residuals(KernelKind kernel, bool graded, double jitter) {
  const GradedBlock b(graded, 14, jitter);
  const double g[3] = {300.0, -120.0, 80.0};  // K/m
  const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), k = 50.0;
  std::vector<double> T(b.n), cond(b.n, k), Q(b.n, 0.0);
  for (std::size_t i = 0; i < b.n; ++i) T[i] = 300.0 + g[0] * b.x[3 * i] + g[1] * b.x[3 * i + 1] + g[2] * b.x[3 * i + 2];
  heat_conduction(b.nl, kernel, b.h_max, b.x.data(), b.volume.data(), T.data(), cond.data(), Q.data(), b.n,
                  graded ? b.h.data() : nullptr);
  HeatResiduals out;
  double total = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < b.n; ++i) {
    const double rel = std::abs(Q[i]) / (b.volume[i] * k * gn / b.s[i]);
    if (b.interior(i)) out.interior = std::max(out.interior, rel);
    else out.face_max = std::max(out.face_max, rel);
    total += Q[i];
    scale += std::abs(Q[i]);
  }
  out.net = std::abs(total) / scale;
  return out;
}

TEST(VariableSpacing, GradedBlockConductsALinearFieldConservatively) {
  for (const KernelKind kernel : {KernelKind::CubicSpline, KernelKind::WendlandC2}) {
    const HeatResiduals uniform = heat_residuals(kernel, false, 0.0);
    const HeatResiduals graded = heat_residuals(kernel, true, 0.0);
    const HeatResiduals disordered = heat_residuals(kernel, false, 0.05);
    const HeatResiduals disordered10 = heat_residuals(kernel, false, 0.10);
    EXPECT_LT(uniform.interior, 1e-10);
    // No bound on graded.interior: see the header (measured, printed, documented).
    for (const HeatResiduals* r : {&uniform, &graded, &disordered, &disordered10}) {
      EXPECT_LT(r->net, 1e-12);       // conservative
      EXPECT_GT(r->face_max, 0.1);    // the yardstick is of order one
    }
    std::printf("%s: interior |Q| / (V k |grad T| / s): uniform %.1e, graded %.4f, 5 %% disorder %.4f, 10 %% disorder "
                "%.4f; faces up to %.2f; net heat %.1e\n",
                kernel == KernelKind::CubicSpline ? "cubic spline" : "Wendland C2", uniform.interior, graded.interior,
                disordered.interior, disordered10.interior, graded.face_max, graded.net);
  }
}

TEST(VariableSpacing, GradedBlockUnderUniformStressFeelsNoMoreThanASlightlyDisorderedLatticeCubicSpline) {
  check_graded(KernelKind::CubicSpline);
}

TEST(VariableSpacing, GradedBlockUnderUniformStressFeelsNoMoreThanASlightlyDisorderedLatticeWendland) {
  check_graded(KernelKind::WendlandC2);
}

}  // namespace
