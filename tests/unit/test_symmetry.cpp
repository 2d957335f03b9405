// Symmetry ghosts (engine/symmetry.hpp, docs/theory.md section 11): the transforms of vectors and
// tensors (invariants preserved), the symmetry group, region membership, the re-entry of particles
// that crossed a cut, the choice of ghosts, and neighbour lists over real + ghost particles.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "engine/neighbours.hpp"
#include "engine/symmetry.hpp"
#include "sphforge/fields.hpp"

using namespace sphforge;
using Vec = Eigen::Vector3d;
using Mat = Eigen::Matrix3d;

namespace {

constexpr double kPi = std::numbers::pi;

Mat full(const double* s) {
  Mat S;
  S << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return S;
}

SymmetrySettings sector(double degrees) {
  SymmetrySettings s;
  s.sector_angle_rad = degrees * kPi / 180.0;
  return s;
}

SymmetrySettings::Plane plane(Vec point, Vec normal) { return {point, normal}; }

}  // namespace

TEST(Symmetry, ReflectedStressAndVector) {
  // Mirror x = 0: P = diag(-1, 1, 1) (eq. 28): v_x and the shear components xy, xz change sign.
  SymmetrySettings s;
  s.mirror_planes = {plane(Vec::Zero(), Vec(1, 0, 0))};
  const Symmetry sym(s);
  ASSERT_EQ(sym.images().size(), 1u);
  const Mat& P = sym.images()[0].Q;
  const double v[3] = {1.0, 2.0, 3.0};
  double w[3];
  Symmetry::transform_vector(P, v, w);
  EXPECT_DOUBLE_EQ(w[0], -1.0);
  EXPECT_DOUBLE_EQ(w[1], 2.0);
  EXPECT_DOUBLE_EQ(w[2], 3.0);
  const double S[6] = {10.0, -4.0, 7.0, 3.0, -2.0, 5.0};  // xx yy zz xy yz xz
  double R[6];
  Symmetry::transform_symmetric(P, S, R);
  const double expected[6] = {10.0, -4.0, 7.0, -3.0, -2.0, -5.0};
  for (int c = 0; c < 6; ++c) EXPECT_DOUBLE_EQ(R[c], expected[c]) << c;
}

TEST(Symmetry, TransformsPreserveInvariants) {
  // An oblique mirror and a 60 deg rotation: trace, second invariant and determinant of a stress,
  // the length of a vector and the invariants of a non-symmetric tensor are unchanged.
  SymmetrySettings a;
  a.mirror_planes = {plane(Vec(0.1, 0.2, 0.3), Vec(1, 2, -2))};
  const Symmetry mirror(a), rotation(sector(60.0));
  ASSERT_EQ(rotation.images().size(), 5u);
  const double S[6] = {10.0, -4.0, 7.0, 3.0, -2.0, 5.0};
  const double v[3] = {0.3, -1.2, 2.5};
  const double A[9] = {1.0, 2.0, -3.0, 0.5, -1.5, 4.0, 2.5, 0.25, 3.0};
  for (const Symmetry* sym : {&mirror, &rotation})
    for (const SymmetryImage& g : sym->images()) {
      EXPECT_NEAR((g.Q.transpose() * g.Q - Mat::Identity()).norm(), 0.0, 1e-14);
      double R[6], w[3], B[9];
      Symmetry::transform_symmetric(g.Q, S, R);
      const Mat s0 = full(S), s1 = full(R);
      EXPECT_NEAR(s1.trace(), s0.trace(), 1e-12);
      EXPECT_NEAR(s1.squaredNorm(), s0.squaredNorm(), 1e-10);
      EXPECT_NEAR(s1.determinant(), s0.determinant(), 1e-9);
      // The transformed tensor is Q S Q^T.
      EXPECT_NEAR((s1 - g.Q * s0 * g.Q.transpose()).norm(), 0.0, 1e-12);
      Symmetry::transform_vector(g.Q, v, w);
      EXPECT_NEAR(Vec(w[0], w[1], w[2]).norm(), Vec(v[0], v[1], v[2]).norm(), 1e-14);
      Symmetry::transform_tensor(g.Q, A, B);
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> a0(A), a1(B);
      EXPECT_NEAR(a1.trace(), a0.trace(), 1e-12);
      EXPECT_NEAR(a1.determinant(), a0.determinant(), 1e-10);
      EXPECT_NEAR((a1 * a1).trace(), (a0 * a0).trace(), 1e-10);
    }
  // The mirror keeps the plane's points: x on the plane maps to itself.
  const SymmetryImage& g = mirror.images()[0];
  const Vec on_plane(0.1, 0.2, 0.3);
  EXPECT_NEAR((g.Q * on_plane + g.t - on_plane).norm(), 0.0, 1e-15);
}

TEST(Symmetry, RigidRotationIsPeriodicInTheSector) {
  // v = w x x maps onto itself under the rotations about z (the swirl of a sector, section 11),
  // and under the mirror z = z0; the mirror x = 0 reverses it (no swirl with such planes).
  SymmetrySettings s = sector(90.0);
  s.mirror_planes = {plane(Vec(0, 0, 0.03), Vec(0, 0, 1))};
  const Symmetry sym(s);
  ASSERT_EQ(sym.images().size(), 7u);
  EXPECT_DOUBLE_EQ(sym.multiplier(), 8.0);
  const Vec omega(0, 0, 2.0), x(0.02, 0.01, 0.005);
  const Vec v = omega.cross(x);
  for (const SymmetryImage& g : sym.images()) {
    const Vec y = g.Q * x + g.t;
    EXPECT_NEAR((g.Q * v - omega.cross(y)).norm(), 0.0, 1e-14);
  }
  // A 90 deg rotation: (1, 0, 0) -> (0, 1, 0), s_xx <-> s_yy, s_xy -> -s_xy.
  const Symmetry quarter(sector(90.0));
  const Mat& R = quarter.images()[0].Q;
  const double e[3] = {1, 0, 0};
  double r[3];
  Symmetry::transform_vector(R, e, r);
  EXPECT_NEAR(r[0], 0.0, 1e-15);
  EXPECT_NEAR(r[1], 1.0, 1e-15);
  const double S[6] = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  double T[6];
  Symmetry::transform_symmetric(R, S, T);
  const double expected[6] = {2.0, 1.0, 3.0, -4.0, 6.0, -5.0};
  for (int c = 0; c < 6; ++c) EXPECT_NEAR(T[c], expected[c], 1e-14) << c;
}

TEST(Symmetry, RejectsUnsupportedSettings) {
  EXPECT_THROW(Symmetry(sector(70.0)), std::invalid_argument);  // 360/70 is not an integer
  EXPECT_THROW(Symmetry(sector(240.0)), std::invalid_argument);
  EXPECT_NO_THROW(Symmetry(sector(45.0)));
  SymmetrySettings oblique;
  oblique.mirror_planes = {plane(Vec::Zero(), Vec(1, 0, 0)), plane(Vec::Zero(), Vec(1, 1, 0))};
  EXPECT_THROW(Symmetry{oblique}, std::invalid_argument);
  SymmetrySettings axial = sector(90.0);
  axial.mirror_planes = {plane(Vec::Zero(), Vec(1, 0, 0))};  // contains the axis: dihedral, not supported
  EXPECT_THROW(Symmetry{axial}, std::invalid_argument);
}

TEST(Symmetry, RegionWrapAndGhosts) {
  const Symmetry quarter(sector(90.0));
  EXPECT_TRUE(quarter.inside(Vec(1, 0, 0)));   // theta = 0 belongs to the sector
  EXPECT_FALSE(quarter.inside(Vec(0, 1, 0)));  // theta = 90 deg is the next sector's
  EXPECT_TRUE(quarter.inside(Vec(0, 0, 5)));   // the axis
  EXPECT_TRUE(quarter.inside(Vec(1, 1, 0)));
  EXPECT_FALSE(quarter.inside(Vec(-1, 1, 0)));
  EXPECT_DOUBLE_EQ(quarter.distance_bound(Vec(1, -0.25, 0)), 0.25);

  // A particle that left through theta = 90 deg re-enters near theta = 0 with its velocity,
  // stress and velocity gradient rotated by -90 deg; scalars unchanged.
  FieldRegistry f;
  f.declare({field::position, 3, "m"}, "test");
  f.declare({field::velocity, 3, "m/s"}, "test");
  f.declare({field::deviatoric_stress, 6, "Pa"}, "test");
  f.declare({field::velocity_gradient, 9, "1/s"}, "test");
  f.declare({field::pressure, 1, "Pa"}, "test");
  f.allocate(2);
  double* x = f.f64(field::position);
  double* v = f.f64(field::velocity);
  double* S = f.f64(field::deviatoric_stress);
  double* L = f.f64(field::velocity_gradient);
  x[0] = 1.0, x[1] = 0.5, x[2] = 0.1;      // inside
  x[3] = -0.01, x[4] = 1.0, x[5] = 0.2;    // just past theta = 90 deg
  v[3] = -1.0, v[4] = 0.0, v[5] = 0.5;
  S[6] = 1.0, S[7] = 2.0, S[8] = 3.0, S[9] = 4.0, S[10] = 5.0, S[11] = 6.0;
  L[9 + 1] = 7.0;  // L_xy
  f.f64(field::pressure)[1] = 42.0;
  EXPECT_EQ(quarter.wrap(f, 2), 1u);
  EXPECT_DOUBLE_EQ(x[0], 1.0);
  EXPECT_NEAR(x[3], 1.0, 1e-15);
  EXPECT_NEAR(x[4], 0.01, 1e-15);
  EXPECT_DOUBLE_EQ(x[5], 0.2);
  EXPECT_TRUE(quarter.inside(Vec(x[3], x[4], x[5])));
  EXPECT_NEAR(v[3], 0.0, 1e-15);
  EXPECT_NEAR(v[4], 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(v[5], 0.5);
  const double expected[6] = {2.0, 1.0, 3.0, -4.0, -6.0, 5.0};  // R(-90 deg) S R^T
  for (int c = 0; c < 6; ++c) EXPECT_NEAR(S[6 + c], expected[c], 1e-14) << c;
  EXPECT_NEAR(L[9 + 3], -7.0, 1e-14);  // L'_yx = -L_xy
  EXPECT_DOUBLE_EQ(f.f64(field::pressure)[1], 42.0);
  // The moves are reported (particle, image) for state kept outside the registry (the friction
  // memory, eq. 32): wrapping the particle past theta = 90 deg again gives particle 1 and the image
  // whose Q moved it, which rotates a vector as the wrap rotated the velocity.
  x[3] = -0.01, x[4] = 1.0, x[5] = 0.2;
  std::vector<std::pair<std::size_t, std::size_t>> moves;
  EXPECT_EQ(quarter.wrap(f, 2, moves), 1u);
  ASSERT_EQ(moves.size(), 1u);
  EXPECT_EQ(moves[0].first, 1u);
  double w[3];
  const double u[3] = {-1.0, 0.0, 0.5};
  Symmetry::transform_vector(quarter.images()[moves[0].second].Q, u, w);
  EXPECT_NEAR(w[0], 0.0, 1e-15);  // round-off of cos(90 deg) ~ 6e-17 times |u| = 1
  EXPECT_NEAR(w[1], 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(w[2], 0.5);
  EXPECT_EQ(quarter.wrap(f, 2, moves), 0u);  // nothing left outside: no moves
  EXPECT_TRUE(moves.empty());

  // Ghosts of a quarter lattice (half-integer sites about the axis): the images within range of
  // the sector; the ghost positions of the full lattice coincide with lattice sites.
  const double dx = 1.0, range = 2.0;
  std::vector<double> pts;
  for (int k = 0; k < 2; ++k)
    for (int j = -5; j < 5; ++j)
      for (int i = -5; i < 5; ++i) {
        const Vec p((i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx);
        if (quarter.inside(p)) pts.insert(pts.end(), {p[0], p[1], p[2]});
      }
  const std::size_t n = pts.size() / 3;
  EXPECT_EQ(n, 50u);
  Symmetry q = quarter;
  q.select(pts.data(), n, range);
  const std::size_t g = q.ghost_count();
  EXPECT_GT(g, 0u);
  pts.resize(3 * (n + g));
  q.fill_positions(pts.data(), n);
  for (std::size_t k = n; k < n + g; ++k) {
    const Vec y(pts[3 * k], pts[3 * k + 1], pts[3 * k + 2]);
    EXPECT_FALSE(q.inside(y));
    EXPECT_LT(q.distance_bound(y), range);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(y[d] / dx - std::floor(y[d] / dx), 0.5, 1e-12);
  }
  // Every full-lattice site within range of a real particle is a real particle or a ghost.
  std::size_t needed = 0;
  for (int k = 0; k < 2; ++k)
    for (int j = -5; j < 5; ++j)
      for (int i = -5; i < 5; ++i) {
        const Vec p((i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx);
        if (q.inside(p)) continue;
        bool near = false;
        for (std::size_t r = 0; r < n && !near; ++r) near = (p - Vec(pts[3 * r], pts[3 * r + 1], pts[3 * r + 2])).norm() < range;
        if (!near) continue;
        ++needed;
        bool found = false;
        for (std::size_t k2 = n; k2 < n + g && !found; ++k2)
          found = (p - Vec(pts[3 * k2], pts[3 * k2 + 1], pts[3 * k2 + 2])).norm() < 1e-12;
        EXPECT_TRUE(found) << p.transpose();
      }
  EXPECT_GT(needed, 0u);

  // Neighbour lists for the real particles only, over real + ghost particles.
  NeighbourList nl;
  nl.rebuild(pts.data(), n + g, range, 0.0, n);
  EXPECT_EQ(nl.count(), n);
  bool any_ghost = false;
  for (std::size_t i = 0; i < n; ++i)
    nl.for_each(i, [&](std::size_t j) { any_ghost = any_ghost || j >= n; });
  EXPECT_TRUE(any_ghost);
}

TEST(Symmetry, FindsParticlesOnOneSpotDirectlyOrThroughTheGroup) {
  // A ring of 12 sites at r = 5 mm in a 90 deg sector, clipped as the core clips (eq. 30).
  const Symmetry quarter(sector(90.0));
  const double dx = 2.0 * kPi * 5e-3 / 12.0, tolerance = 1e-6 * dx;
  auto ring = [&](double phase) {
    std::vector<Vec> kept;
    for (int a = 0; a < 12; ++a) {
      const double angle = 2.0 * kPi * (a + phase) / 12.0;
      const Vec x(5e-3 * std::cos(angle), 5e-3 * std::sin(angle), 1e-3);
      if (quarter.inside(x)) kept.push_back(x);
    }
    return kept;
  };
  // Phase 1/4 (eq. 79): three sites, none on a cut, the pitch kept across the cuts: no pair.
  const std::vector<Vec> shifted = ring(0.25);
  ASSERT_EQ(shifted.size(), 3u);
  EXPECT_EQ(quarter.find_coincident(shifted, dx, tolerance), std::make_pair(shifted.size(), shifted.size()));
  // Phase 0: the site at theta = 0 is kept, and its twin at theta = 90 deg is kept too when round-off
  // puts it at 90 deg - eps (here cos(pi/2) > 0 leaves it at 90 deg exactly, so it is placed by
  // hand, 1e-18 m off the axis x = 0); the twin is the image of the first under the rotation by 90 deg.
  std::vector<Vec> on_cut = ring(0.0);
  ASSERT_EQ(on_cut.size(), 3u);
  on_cut.emplace_back(1e-18, 5e-3, 1e-3);
  ASSERT_TRUE(quarter.inside(on_cut.back()));
  const auto [i, j] = quarter.find_coincident(on_cut, dx, tolerance);
  ASSERT_LT(i, on_cut.size());
  EXPECT_NE(i, j);
  EXPECT_NEAR(std::min(std::atan2(on_cut[i].y(), on_cut[i].x()), std::atan2(on_cut[j].y(), on_cut[j].x())), 0.0, 1e-12);
  // Without symmetry the ring's sites are a pitch apart; a copied site is found directly.
  const Symmetry none;
  EXPECT_EQ(none.find_coincident(on_cut, dx, tolerance).first, on_cut.size());
  std::vector<Vec> copied = shifted;
  copied.push_back(shifted[1] + Vec(0.3 * tolerance, 0.0, 0.0));
  EXPECT_EQ(none.find_coincident(copied, dx, tolerance), std::make_pair(std::size_t(1), std::size_t(3)));
  // A site on a mirror plane is its own image, not a pair.
  SymmetrySettings mirror;
  mirror.mirror_planes = {plane(Vec::Zero(), Vec::UnitX())};
  const std::vector<Vec> on_plane = {Vec(0.0, 1e-3, 0.0), Vec(1e-3, 1e-3, 0.0)};
  EXPECT_EQ(Symmetry(mirror).find_coincident(on_plane, 1e-3, 1e-9).first, on_plane.size());
}
