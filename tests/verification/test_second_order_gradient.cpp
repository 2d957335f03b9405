// Verification (label `verification`): the second-order (quadratic-consistent) gradient correction
// (theory section 18, eqs. 130-137; engine/second_order_gradient.cpp).
//
// 1. Quadratic patch test: on a 3D block jittered by up to 20 % of dx, a quadratic velocity field
//    v_a = A_ab x_b + 1/2 H_abc x_b x_c must come out as L = A + H x at every particle where the
//    second-order correction applied (gradient_condition != -1), free-surface and corner particles
//    included. Tolerance 1e-8 relative to |A|: only round-off is left (eq. 132 is an exact identity
//    for quadratics); the sums over ~100 neighbours carry ~1e-14 relative error and the 9 x 9 solve
//    multiplies it by at most cond(M2) < 1e5 (eq. 134), so ~1e-9 is the worst round-off; the
//    first-order correction misses the same field by more than 1e-2 at the surface (asserted below),
//    so the test separates the two by six orders of magnitude.
// 2. The plate's lattice (the hypothesis of docs/verification.md section 3): pure bending across a
//    beam 4 particles thick, dv_x/dx = -kappa y. The first-order correction evaluates it at the
//    outer fibre as if the fibre were nearer the axis; the second order is exact there. Next to the
//    plate's clamp (v = 0 behind x = 0) the first two free columns still fit across the clamp face.
// 3. Duality with the momentum term (eq. 136): for random stresses and velocities, the internal
//    forces' power sum_i m_i a_i . v_i equals minus the stress power sum_i V_i sigma_i : L_i (eq. 137),
//    sum_i m_i a_i = 0 and sum_i x_i x m_i a_i = 0, all to round-off (1e-10 relative: the same
//    round-off argument as 1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "engine/neighbours.hpp"
#include "engine/second_order_gradient.hpp"
#include "engine/sph_operators.hpp"

namespace {

using namespace sphforge;

struct Cloud {
  std::size_t n = 0;
  double dx = 1e-3, h = 1.3e-3;
  std::vector<double> x, volume;
  std::vector<bool> surface;
  NeighbourList nl;
  void finish() {
    n = x.size() / 3;
    volume.assign(n, dx * dx * dx);
    nl.build(x.data(), n, kernel_support_radius(h) + 0.2 * h);  // with a Verlet skin, as in a run
  }
};

Cloud jittered_block(int side) {
  Cloud c;
  std::mt19937 rng(20261130);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        const int lattice[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) c.x.push_back((lattice[d] + jitter(rng)) * c.dx);
        c.surface.push_back(i == 0 || j == 0 || k == 0 || i == side - 1 || j == side - 1 || k == side - 1);
      }
  c.finish();
  return c;
}

/// Both velocity gradients of the field v on the cloud: the first-order corrected one (eqs. 3a-3b)
/// and the second-order one (eqs. 131-133) with its matrices B, C and the condition estimate.
struct Gradients {
  std::vector<double> first, second, B, C, condition;
};
Gradients gradients(const Cloud& c, KernelKind kernel, const std::vector<double>& v) {
  Gradients g{std::vector<double>(9 * c.n), std::vector<double>(9 * c.n), std::vector<double>(27 * c.n),
              std::vector<double>(6 * c.n), std::vector<double>(c.n)};
  velocity_gradient(c.nl, kernel, c.h, c.x.data(), v.data(), c.volume.data(), true, g.first.data(), nullptr, nullptr,
                    c.n);
  second_order_correction(c.nl, kernel, c.h, c.x.data(), c.volume.data(), g.B.data(), g.C.data(), g.condition.data(),
                          c.n);
  second_order_velocity_gradient(c.nl, kernel, c.h, c.x.data(), v.data(), c.volume.data(), g.B.data(), g.C.data(),
                                 g.second.data(), c.n);
  return g;
}

// v_a = A_ab x_b + 1/2 H_abc x_b x_c (H symmetric in b, c), gradient A + H x.
struct QuadraticField {
  double A[3][3] = {{0.3, -1.2, 0.5}, {2.0, 0.7, -0.4}, {-0.9, 1.1, -1.5}};  // 1/s
  double H[3][3][3];                                                         // 1/(m s)
  QuadraticField() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-300.0, 300.0);  // H dx ~ 0.3 |A|: a strongly curved field
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = b; c < 3; ++c) H[a][b][c] = H[a][c][b] = u(rng);
  }
  void velocity(const double* x, double* v) const {
    for (int a = 0; a < 3; ++a) {
      v[a] = 0.0;
      for (int b = 0; b < 3; ++b) {
        v[a] += A[a][b] * x[b];
        for (int c = 0; c < 3; ++c) v[a] += 0.5 * H[a][b][c] * x[b] * x[c];
      }
    }
  }
  double gradient(const double* x, int a, int b) const {
    double g = A[a][b];
    for (int c = 0; c < 3; ++c) g += H[a][b][c] * x[c];
    return g;
  }
  double norm_a() const {
    double s = 0.0;
    for (auto& row : A)
      for (double c : row) s += c * c;
    return std::sqrt(s);
  }
};

double max_error(const Cloud& c, const QuadraticField& f, const std::vector<double>& L,
                 const std::vector<bool>& use) {
  double worst = 0.0;
  for (std::size_t i = 0; i < c.n; ++i) {
    if (!use[i]) continue;
    double e = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) e += std::pow(L[9 * i + 3 * a + b] - f.gradient(&c.x[3 * i], a, b), 2);
    worst = std::max(worst, std::sqrt(e) / f.norm_a());
  }
  return worst;
}

void check_quadratic_patch(KernelKind kernel) {
  const Cloud c = jittered_block(12);
  const QuadraticField f;
  std::vector<double> v(3 * c.n);
  for (std::size_t i = 0; i < c.n; ++i) f.velocity(&c.x[3 * i], &v[3 * i]);
  const Gradients g = gradients(c, kernel, v);
  const std::vector<double>&L = g.second, &condition = g.condition;
  std::vector<bool> second(c.n), second_surface(c.n);
  std::size_t count = 0, count_surface = 0;
  double worst_condition = 0.0;
  for (std::size_t i = 0; i < c.n; ++i) {
    second[i] = condition[i] != -1.0;
    second_surface[i] = second[i] && c.surface[i];
    count += second[i];
    count_surface += second_surface[i];
    worst_condition = std::max(worst_condition, condition[i]);
  }
  // The correction must apply almost everywhere, surfaces included, or the test would prove little.
  EXPECT_GT(count, c.n * 95 / 100);
  EXPECT_GT(count_surface, 500u);
  const double e2 = max_error(c, f, L, second), e2s = max_error(c, f, L, second_surface);
  EXPECT_LT(e2, 1e-8);
  EXPECT_LT(e2s, 1e-8);

  // The first-order correction on the same particles: exact for linear fields only.
  const double e1s = max_error(c, f, g.first, second_surface);
  EXPECT_GT(e1s, 1e-2);
  std::printf("quadratic patch (%s): second order max error %.2e (surface %.2e), first order at the surface %.2e; "
              "largest condition %.0f; second order at %zu of %zu particles\n",
              kernel == KernelKind::WendlandC2 ? "wendland_c2" : "cubic_spline", e2, e2s, e1s, worst_condition, count,
              c.n);
}

TEST(SecondOrderGradient, QuadraticVelocityExactOnJitteredBlockCubicSpline) {
  check_quadratic_patch(KernelKind::CubicSpline);
}
TEST(SecondOrderGradient, QuadraticVelocityExactOnJitteredBlockWendlandC2) {
  check_quadratic_patch(KernelKind::WendlandC2);
}

// The plate of cases/verification/oscillating_plate.json at dx = H/4 (h = 1.3 dx): pure bending about
// the beam's axis, v_x = -kappa x y', v_y = kappa x^2 / 2 (y' from the mid-plane), so dv_x/dx = -kappa y'.
TEST(SecondOrderGradient, BendingStrainAtTheOuterFibreOfThePlateLattice) {
  Cloud c;
  c.dx = 5e-3;
  c.h = 1.3 * c.dx;
  const int nx = 16, ny = 4, nz = 4;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        c.x.push_back((i + 0.5) * c.dx);
        c.x.push_back((j + 0.5) * c.dx);
        c.x.push_back((k + 0.5) * c.dx);
      }
  c.finish();
  const double kappa = 1.0, y_mid = 0.5 * ny * c.dx;  // 1/m; any curvature, the operators are linear
  std::vector<double> v(3 * c.n, 0.0);
  for (std::size_t i = 0; i < c.n; ++i) {
    const double x = c.x[3 * i], y = c.x[3 * i + 1] - y_mid;
    v[3 * i] = -kappa * x * y;
    v[3 * i + 1] = 0.5 * kappa * x * x;
  }
  const Gradients g = gradients(c, KernelKind::CubicSpline, v);
  const std::vector<double>&L1 = g.first, &L2 = g.second, &condition = g.condition;
  // A particle in the middle of the length (away from the beam's ends), at each fibre across the
  // thickness and on the side face z = dx/2 (one-sided also in z).
  for (int j = 0; j < ny; ++j) {
    const std::size_t i = static_cast<std::size_t>((1 * ny + j) * nx + nx / 2);
    const double exact = -kappa * (c.x[3 * i + 1] - y_mid);
    const double r1 = L1[9 * i] / exact, r2 = L2[9 * i] / exact;
    std::printf("plate lattice H/4, fibre y' = %+.1f dx: dv_x/dx first order / exact = %.4f, second order / exact "
                "= %.12f (condition %.0f)\n",
                (c.x[3 * i + 1] - y_mid) / c.dx, r1, r2, condition[i]);
    EXPECT_NE(condition[i], -1.0);
    // Round-off only (see the header): the field is quadratic.
    EXPECT_NEAR(r2, 1.0, 1e-8);
  }
  // The hypothesis: at the outer fibre (one-sided across the thickness) the first-order gradient
  // under-estimates the bending strain. Asserted as "at least 5 % too small", the size that matters
  // for the period (the period goes with the inverse square root of the bending stiffness).
  const std::size_t outer = static_cast<std::size_t>((1 * ny + (ny - 1)) * nx + nx / 2);
  EXPECT_LT(L1[9 * outer] / (-kappa * (c.x[3 * outer + 1] - y_mid)), 0.95);
}

// The clamp of the plate case (docs/verification.md section 3): particles behind x = 0 are held at
// v = 0 while the beam bends from x = 0 on. Pure bending for x > 0 (v_x = -kappa x y',
// v_y = kappa x^2 / 2) and v = 0 for x < 0: the exact strain of the free particles is -kappa y'.
// The fits of the first free columns reach across the face into the clamp, where the curvature
// jumps to zero, so even the second order sees less than the exact strain there: the root is too
// soft over about one spacing. Asserted: the first free column sees under 95 % of the exact strain
// at the outer fibre (what makes the root soft), the fourth column (beyond the support 2h = 2.6 dx)
// the exact strain to round-off.
TEST(SecondOrderGradient, BendingStrainNextToTheClampOfThePlateLattice) {
  Cloud c;
  c.dx = 5e-3;
  c.h = 1.3 * c.dx;
  const int nx = 16, ny = 4, nz = 4, clamped = 6;  // columns i < clamped lie behind x = 0
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        c.x.push_back((i - clamped + 0.5) * c.dx);
        c.x.push_back((j + 0.5) * c.dx);
        c.x.push_back((k + 0.5) * c.dx);
      }
  c.finish();
  const double kappa = 1.0, y_mid = 0.5 * ny * c.dx;
  std::vector<double> v(3 * c.n, 0.0);
  for (std::size_t i = 0; i < c.n; ++i) {
    const double x = c.x[3 * i], y = c.x[3 * i + 1] - y_mid;
    if (x < 0.0) continue;
    v[3 * i] = -kappa * x * y;
    v[3 * i + 1] = 0.5 * kappa * x * x;
  }
  const Gradients g = gradients(c, KernelKind::CubicSpline, v);
  const std::vector<double>&L1 = g.first, &L2 = g.second;
  double ratio[4] = {};
  for (int col = 0; col < 4; ++col) {
    // outer fibre (j = ny - 1), second layer in z
    const std::size_t i = static_cast<std::size_t>((1 * ny + (ny - 1)) * nx + clamped + col);
    const double exact = -kappa * (c.x[3 * i + 1] - y_mid);
    ratio[col] = L2[9 * i] / exact;
    std::printf("next to the clamp, outer fibre, x = %.1f dx: dv_x/dx first order / exact = %.4f, second order / "
                "exact = %.4f\n",
                c.x[3 * i] / c.dx, L1[9 * i] / exact, ratio[col]);
  }
  EXPECT_LT(ratio[0], 0.95);
  EXPECT_NEAR(ratio[3], 1.0, 1e-8);  // round-off only, as in the tests above
}

// eq. 137: the momentum term of eq. 136 (with the first-order part of eq. 7 for the fallback
// particles) is the exact dual of the gradient of eq. 133.
TEST(SecondOrderGradient, MomentumTermIsDualToTheGradient) {
  const Cloud c = jittered_block(8);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> v(3 * c.n), S(6 * c.n), p(c.n), mass(c.n), density(c.n);
  for (double& e : v) e = u(rng);
  for (double& e : S) e = 1e6 * u(rng);
  for (double& e : p) e = 1e6 * u(rng);
  for (std::size_t i = 0; i < c.n; ++i) {
    density[i] = 1000.0 * (1.0 + 0.1 * u(rng));
    mass[i] = density[i] * c.volume[i];
  }
  const Gradients g = gradients(c, KernelKind::CubicSpline, v);
  const std::vector<double>&B = g.B, &C = g.C, &L = g.second;
  std::vector<double> stress_c(9 * c.n), stress_b(27 * c.n), a(3 * c.n);
  corrected_stress(p.data(), S.data(), C.data(), true, stress_c.data(), c.n);
  second_order_stress(p.data(), S.data(), B.data(), stress_b.data(), c.n);
  ArtificialViscosity no_viscosity{0.0, 0.0, 0.1};
  ArtificialStress no_stress{0.0, 4.0, 1.0};
  momentum_rate(c.nl, KernelKind::CubicSpline, c.h, no_viscosity, 1.0, c.x.data(), v.data(), mass.data(),
                density.data(), c.volume.data(), stress_c.data(), no_stress, nullptr, nullptr, a.data(), c.n);
  second_order_momentum_term(c.nl, KernelKind::CubicSpline, c.h, c.x.data(), mass.data(), c.volume.data(),
                             stress_b.data(), a.data(), c.n);
  double kinetic_rate = 0.0, stress_power = 0.0, scale = 0.0, force[3] = {0, 0, 0}, force_scale = 0.0;
  double torque[3] = {0, 0, 0}, torque_scale = 0.0;
  for (std::size_t i = 0; i < c.n; ++i) {
    const double* s = &S[6 * i];
    const double sigma[9] = {s[0] - p[i], s[3], s[5], s[3], s[1] - p[i], s[4], s[5], s[4], s[2] - p[i]};
    for (int k = 0; k < 9; ++k) {
      stress_power += c.volume[i] * sigma[k] * L[9 * i + k];
      scale += std::abs(c.volume[i] * sigma[k] * L[9 * i + k]);
    }
    for (int d = 0; d < 3; ++d) {
      kinetic_rate += mass[i] * a[3 * i + d] * v[3 * i + d];
      force[d] += mass[i] * a[3 * i + d];
      force_scale += std::abs(mass[i] * a[3 * i + d]);
    }
    const double* xi = &c.x[3 * i];
    const double f[3] = {mass[i] * a[3 * i], mass[i] * a[3 * i + 1], mass[i] * a[3 * i + 2]};
    torque[0] += xi[1] * f[2] - xi[2] * f[1];
    torque[1] += xi[2] * f[0] - xi[0] * f[2];
    torque[2] += xi[0] * f[1] - xi[1] * f[0];
    torque_scale += std::sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]) * (std::abs(f[0]) + std::abs(f[1]) + std::abs(f[2]));
  }
  std::printf("duality: sum m a.v = %.6e W, -sum V sigma:L = %.6e W (scale %.3e); |sum m a| = %.3e N of %.3e\n",
              kinetic_rate, -stress_power, scale, std::hypot(force[0], force[1], force[2]), force_scale);
  EXPECT_NEAR(kinetic_rate, -stress_power, 1e-10 * scale);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(force[d], 0.0, 1e-10 * force_scale);
  // Angular momentum (eq. 137): every particle of this block uses the second order, which is exact
  // for linear fields, so the torques cancel to round-off.
  std::printf("torque: |sum x x m a| = %.3e N m of %.3e\n", std::hypot(torque[0], torque[1], torque[2]), torque_scale);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(torque[d], 0.0, 1e-10 * torque_scale);
}

}  // namespace
