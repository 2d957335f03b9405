// Rigid tool geometry and kinematics against analytic values (docs/theory.md eqs. 40-46;
// docs/verification.md section 10). Distances are compared to round-off: every shape is exact
// (no chords), so the tolerances below are a few ulps of the lengths involved.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "sphforge/tool.hpp"
#include "tools/shapes.hpp"
#include "uv_sphere.hpp"

using namespace sphforge;
using Vec = Eigen::Vector3d;

namespace {

// Round-off of lengths of order 1 m (and of the mm-scale ones below): a few ulps of the
// coordinates that enter each formula.
constexpr double kExact = 1e-13;

void expect_vec_near(const Vec& a, const Vec& b, double tol) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
  EXPECT_NEAR(a.z(), b.z(), tol);
}

const std::string kBoxStl = std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/tools/box_10mm.stl";

}  // namespace

TEST(Tools, PlaneOfAnyOrientation) {
  const Vec p0(0.1, -0.2, 0.3), n = Vec(1.0, 2.0, -2.0) / 3.0;
  RigidTool plane = RigidTool::plane("p", p0, Vec(1.0, 2.0, -2.0), 0.5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int k = 0; k < 100; ++k) {
    const Vec x = p0 + Vec(u(rng), u(rng), u(rng));
    Vec normal;
    EXPECT_NEAR(plane.signed_distance(x, normal), (x - p0).dot(n), kExact);
    expect_vec_near(normal, n, kExact);
  }
  // Moved along z by s and turned about z by theta: the plane through R p0 + s e_z, normal R n.
  plane.axial_offset_m = 0.05;
  plane.angle_rad = 0.7;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec::UnitZ()).toRotationMatrix();
  const Vec q0 = R * p0 + Vec(0, 0, 0.05), m = R * n;
  for (int k = 0; k < 100; ++k) {
    const Vec x = q0 + Vec(u(rng), u(rng), u(rng));
    Vec normal;
    EXPECT_NEAR(plane.signed_distance(x, normal), (x - q0).dot(m), kExact);
    expect_vec_near(normal, m, kExact);
  }
}

TEST(Tools, CylinderInsideAndOutside) {
  const double R = 0.1;
  const RigidTool barrel = RigidTool::cylinder("barrel", R, 0.0, 0.2, true);
  const RigidTool pin = RigidTool::cylinder("pin", R, 0.0, 0.2, false);
  const double phi = 0.9;
  const Vec er(std::cos(phi), std::sin(phi), 0.0);
  for (double r : {0.0, 0.03, 0.099, 0.1, 0.13}) {
    const Vec x = r * er + Vec(0, 0, 0.07);
    Vec n1, n2;
    EXPECT_NEAR(barrel.signed_distance(x, n1), R - r, kExact) << r;
    EXPECT_NEAR(pin.signed_distance(x, n2), r - R, kExact) << r;
    if (r > 0.0) {  // on the axis the radial direction is arbitrary
      expect_vec_near(n1, -er, kExact);
      expect_vec_near(n2, er, kExact);
    }
    EXPECT_NEAR(n1.norm(), 1.0, kExact);
  }
  // Beyond the end z = 0.2 the nearest point is the rim circle.
  Vec n;
  EXPECT_NEAR(barrel.signed_distance(0.05 * er + Vec(0, 0, 0.3), n), std::hypot(0.05, 0.1), kExact);
  expect_vec_near(n, (Vec(0, 0, 0.1) - 0.05 * er).normalized(), kExact);
}

TEST(Tools, ConeAndTheAxis) {
  // The cone r = z for 0 <= z <= 1, workpiece above it (walked outwards: normal (-1, 1)/sqrt 2).
  const RigidTool cone("cone", std::vector<Eigen::Vector2d>{{0.0, 0.0}, {1.0, 1.0}});
  const double s = std::sqrt(0.5);
  const Vec er(0.6, 0.8, 0.0);
  Vec n;
  EXPECT_NEAR(cone.signed_distance(0.2 * er + Vec(0, 0, 0.6), n), 0.4 * s, kExact);
  expect_vec_near(n, s * (Vec(0, 0, 1) - er), kExact);
  EXPECT_NEAR(cone.signed_distance(0.7 * er + Vec(0, 0, 0.5), n), -0.2 * s, kExact);
  expect_vec_near(n, s * (Vec(0, 0, 1) - er), kExact);
  // On the axis, z = 0.5: every point of the circle r = z = 0.25 is nearest, at 0.5/sqrt 2.
  EXPECT_NEAR(cone.signed_distance(Vec(0, 0, 0.5), n), 0.5 * s, kExact);
  EXPECT_NEAR(n.z(), s, kExact);
  EXPECT_NEAR(n.norm(), 1.0, kExact);
  // Below the apex on the axis: the apex is nearest.
  EXPECT_NEAR(cone.signed_distance(Vec(0, 0, -0.3), n), -0.3, kExact);
}

TEST(Tools, FilletArcIsExact) {
  // A die: underside walked inwards at z = -3f, land r = Rd walked up, face z = 0 walked out,
  // the entry corner (Rd, 0) rounded by a fillet f: arc centre (Rd + f, -f).
  const double Rd = 0.01, Rb = 0.03, f = 0.002;
  const ToolProfile sharp({{Rb, -3 * f}, {Rd, -3 * f}, {Rd, 0.0}, {Rb, 0.0}});
  const ToolProfile round = sharp.with_fillets(f, {2});
  ASSERT_EQ(round.segments().size(), 4u);
  EXPECT_TRUE(round.segments()[2].arc);
  const RigidTool die("die", round);
  const Eigen::Vector2d c(Rd + f, -f);
  const Eigen::Vector2d diag = Eigen::Vector2d(-1.0, 1.0).normalized();
  auto at = [](const Eigen::Vector2d& rz) { return Vec(rz.x(), 0.0, rz.y()); };
  Vec n;
  for (double h : {0.0005, 0.0019, -0.0005, -0.0015}) {
    // Along the diagonal from the centre: distance |q - c| - f, normal radial (outward of the tool).
    EXPECT_NEAR(die.signed_distance(at(c + (f + h) * diag), n), h, kExact) << h;
    expect_vec_near(n, Vec(diag.x(), 0.0, diag.y()), 1e-12);
  }
  // At other angles within the arc too (exact arc: no chord error at all).
  for (double a : {0.05, 0.3, 0.7, 1.2, 1.5}) {
    const Eigen::Vector2d dir(-std::cos(a), std::sin(a));  // from the centre towards the workpiece
    EXPECT_NEAR(die.signed_distance(at(c + 1.3 * f * dir), n), 0.3 * f, kExact) << a;
  }
  // The old sharp corner is now in the gap the fillet opened: distance f (sqrt 2 - 1).
  EXPECT_NEAR(die.signed_distance(at({Rd, 0.0}), n), f * (std::sqrt(2.0) - 1.0), kExact);
  // At the centre: every point of the arc at distance f, inside the tool.
  EXPECT_NEAR(die.signed_distance(at(c), n), -f, kExact);
  // On the land below the fillet and on the face beyond it.
  EXPECT_NEAR(die.signed_distance(at({Rd - 0.001, -2 * f}), n), 0.001, kExact);
  expect_vec_near(n, Vec(-1, 0, 0), kExact);
  EXPECT_NEAR(die.signed_distance(at({Rd + 2 * f, 0.0015}), n), 0.0015, kExact);
  expect_vec_near(n, Vec(0, 0, 1), kExact);
  // Sharp convex corner at the exit (Rd, -3f): outside it the corner is nearest, inside it the
  // nearer side (pseudo-normal sign).
  EXPECT_NEAR(die.signed_distance(at({Rd - 0.0003, -3 * f - 0.0004}), n), 0.0005, kExact);
  EXPECT_NEAR(die.signed_distance(at({Rd + 0.0003, -3 * f + 0.0001}), n), -0.0001, kExact);
  expect_vec_near(n, Vec(0, 0, -1), kExact);
  // On the axis below the die: nearest is the land's exit corner circle.
  EXPECT_NEAR(die.signed_distance(Vec(0, 0, -3 * f - 0.004), n), std::hypot(Rd, 0.004), kExact);
}

TEST(Tools, SphericalDieFromAFillet) {
  // A hemispherical die of radius R about the origin, workpiece inside: the corner of
  // (0, -R) -> (R, -R) -> (R, 0) rounded with radius R is exactly the quarter circle (eq. 41).
  const double R = 0.02;
  const RigidTool bowl("bowl", ToolProfile({{0.0, -R}, {R, -R}, {R, 0.0}}).with_fillets(R));
  const Vec dir = Vec(0.3, -0.4, -0.5).normalized();
  Vec n;
  for (double rho : {0.0001, 0.01, 0.019, 0.021}) {
    EXPECT_NEAR(bowl.signed_distance(rho * dir, n), R - rho, kExact) << rho;
    expect_vec_near(n, -dir, 1e-12);
  }
  // On the axis: the bottom of the bowl is nearest.
  EXPECT_NEAR(bowl.signed_distance(Vec(0, 0, -0.5 * R), n), 0.5 * R, kExact);
  expect_vec_near(n, Vec(0, 0, 1), kExact);
}

TEST(Tools, ConcaveCornerSign) {
  // Face z = 0 walked out to r = 1, then a wall r = 1 walked up: the workpiece fills r < 1, z > 0.
  const RigidTool cup("cup", std::vector<Eigen::Vector2d>{{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}});
  Vec n;
  EXPECT_NEAR(cup.signed_distance(Vec(1.2, 0, -0.1), n), -std::hypot(0.2, 0.1), kExact);
  EXPECT_NEAR(cup.signed_distance(Vec(0.9, 0, 0.05), n), 0.05, kExact);
  EXPECT_NEAR(cup.signed_distance(Vec(1.2, 0, 0.5), n), -0.2, kExact);
  expect_vec_near(n, Vec(-1, 0, 0), kExact);
}

TEST(Tools, FilletMatchesAFineChordApproximation) {
  // Cross-check of the arc formulas: random points against the profile with its arcs replaced
  // by chords of 1e-4 rad, whose sagitta f (1 - cos 5e-5) ~ 1.3e-9 f bounds the difference.
  const double f = 0.2;
  const ToolProfile round = ToolProfile({{2.0, -1.0}, {1.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}}).with_fillets(f);
  const ToolProfile chords(round.sample(1e-4));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ur(0.0, 2.2), uz(-1.5, 1.5);
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector2d q(ur(rng), uz(rng));
    Eigen::Vector2d n1, n2;
    const double d1 = round.signed_distance(q, n1), d2 = chords.signed_distance(q, n2);
    EXPECT_NEAR(d1, d2, 2e-9 * f) << q.transpose();
  }
}

TEST(Tools, FilletThatDoesNotFitIsRejected) {
  const ToolProfile p({{1.0, -0.1}, {1.0, 0.0}, {2.0, 0.0}});
  EXPECT_THROW(p.with_fillets(0.2), std::invalid_argument);  // needs 0.2 of a 0.1 long land
  EXPECT_NO_THROW(p.with_fillets(0.1));
  EXPECT_THROW(p.with_fillets(0.05, {0}), std::invalid_argument);  // an end is no corner
}

TEST(Tools, StlBox) {
  RigidTool box = RigidTool::stl("box", kBoxStl, 1e-3);  // a 10 mm cube about the origin
  const double mm = 1e-3;
  Vec n;
  EXPECT_NEAR(box.signed_distance(Vec(0, 0, 8 * mm), n), 3 * mm, kExact);
  expect_vec_near(n, Vec(0, 0, 1), kExact);
  EXPECT_NEAR(box.signed_distance(Vec(7 * mm, 7 * mm, 1 * mm), n), std::hypot(2, 2) * mm, kExact);
  expect_vec_near(n, Vec(1, 1, 0).normalized(), kExact);
  EXPECT_NEAR(box.signed_distance(Vec(-6 * mm, 6 * mm, -6 * mm), n), std::sqrt(3.0) * mm, kExact);
  expect_vec_near(n, Vec(-1, 1, -1).normalized(), kExact);
  EXPECT_NEAR(box.signed_distance(Vec(0, 0, 3 * mm), n), -2 * mm, kExact);
  expect_vec_near(n, Vec(0, 0, 1), kExact);
  EXPECT_NEAR(box.signed_distance(Vec(4 * mm, 1 * mm, 0), n), -1 * mm, kExact);
  expect_vec_near(n, Vec(1, 0, 0), kExact);
  EXPECT_NEAR(box.signed_distance(Vec(4 * mm, 4.5 * mm, 4.2 * mm), n), -0.5 * mm, kExact);
  expect_vec_near(n, Vec(0, 1, 0), kExact);
  // Turned by 45 degrees about z and lifted by 2 mm: a vertical edge now points along +x at
  // 5 sqrt 2 mm from the axis.
  box.angle_rad = std::numbers::pi / 4;
  box.axial_offset_m = 2 * mm;
  EXPECT_NEAR(box.signed_distance(Vec(10 * mm, 0, 2 * mm), n), (10 - 5 * std::sqrt(2.0)) * mm, kExact);
  expect_vec_near(n, Vec(1, 0, 0), kExact);
  EXPECT_NEAR(box.signed_distance(Vec(0, 0, 9 * mm), n), 2 * mm, kExact);
  Vec lo, hi;
  box.bounds(lo, hi);
  EXPECT_NEAR(hi.x(), 5 * std::sqrt(2.0) * mm, kExact);
  EXPECT_NEAR(lo.z(), -3 * mm, kExact);
  EXPECT_NEAR(hi.z(), 7 * mm, kExact);
}

TEST(Tools, StlErrors) {
  EXPECT_THROW(RigidTool::stl("x", kBoxStl + ".missing"), std::runtime_error);
}

TEST(Tools, HierarchyEqualsBruteForceOnATessellatedSphere) {
  // A UV sphere of radius 1 (40 x 80 facets): the hierarchy must return exactly what the scan
  // over every triangle returns; both lie within the tessellation error of the true sphere.
  const int nt = 40, np = 80;
  const sphforge_test::TriangleMesh sphere_mesh = sphforge_test::uv_sphere(1.0, nt, np);
  const auto& points = sphere_mesh.points;
  const auto& tris = sphere_mesh.triangles;
  const auto mesh = make_mesh_shape(points, tris);
  const RigidTool sphere("sphere", mesh);
  // Tessellation error bound: every point of a triangle lies in its circumscribed disc, whose
  // plane is sqrt(1 - rho^2) from the centre, so the mesh lies between the radii sqrt(1 - rho^2)
  // and 1 (rho: the largest circumradius); distances to the two surfaces differ by at most that gap.
  double rho_max = 0.0;
  for (const auto& t : tris) {
    const double a = (points[t[1]] - points[t[2]]).norm(), b = (points[t[0]] - points[t[2]]).norm(),
                 c = (points[t[0]] - points[t[1]]).norm();
    const double area2 = (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]).norm();
    rho_max = std::max(rho_max, a * b * c / (2.0 * area2));
  }
  const double facet_gap = 1.0 - std::sqrt(1.0 - rho_max * rho_max);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 3000; ++k) {
    const Vec x(u(rng), u(rng), u(rng));
    Vec n_tree, n_brute;
    const double d_tree = sphere.signed_distance(x, n_tree);
    const double d_brute = mesh_signed_distance_brute_force(*mesh, x, n_brute);
    EXPECT_EQ(d_tree, d_brute) << x.transpose();
    EXPECT_NEAR(d_tree, x.norm() - 1.0, facet_gap) << x.transpose();
  }
}

TEST(Tools, BatchQueryMatchesSingleAndCulls) {
  RigidTool die("die", ToolProfile({{0.03, -0.006}, {0.01, -0.006}, {0.01, 0.0}, {0.03, 0.0}}).with_fillets(0.002, {2}));
  die.axial_offset_m = 0.01;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  const std::size_t n = 1000;
  std::vector<double> x(3 * n), d(n), normal(3 * n);
  for (double& v : x) v = u(rng);
  const double cutoff = 0.002;
  die.signed_distance(n, x.data(), d.data(), normal.data(), cutoff);
  Vec lo, hi;
  die.bounds(lo, hi);
  std::size_t culled = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec xi(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    const bool inside = ((xi.array() >= lo.array() - cutoff) && (xi.array() <= hi.array() + cutoff)).all();
    if (!inside) {
      EXPECT_TRUE(std::isinf(d[i]));
      ++culled;
      continue;
    }
    Vec ns;
    EXPECT_EQ(d[i], die.signed_distance(xi, ns));
    expect_vec_near(Vec(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]), ns, 0.0);
  }
  EXPECT_GT(culled, 0u);
  EXPECT_LT(culled, n);
}

TEST(Tools, SurfaceVelocity) {
  RigidTool t = RigidTool::cylinder("c", 0.1, 0.0, 1.0, true);
  t.axial_velocity_m_s = -0.02;
  t.angular_velocity_rad_s = 3.0;
  expect_vec_near(t.surface_velocity(Vec(0.1, 0.05, 0.3)), Vec(-3.0 * 0.05, 3.0 * 0.1, -0.02), kExact);
}

TEST(Tools, ScheduleLandsOnItsIntegral) {
  // v(t): 0 -> 2 m/s over 1 s, then 2 m/s until 2 s, then down to -1 m/s at 3 s, held after.
  const PiecewiseLinear s({{0.0, 0.0}, {1.0, 2.0}, {2.0, 2.0}, {3.0, -1.0}});
  EXPECT_DOUBLE_EQ(s.value(0.5), 1.0);
  EXPECT_DOUBLE_EQ(s.value(2.5), 0.5);
  EXPECT_DOUBLE_EQ(s.value(7.0), -1.0);
  EXPECT_NEAR(s.integral(0.0, 3.0), 1.0 + 2.0 + 0.5, kExact);
  // Steps of uneven length, crossing the knots: the pose follows the exact integral.
  RigidTool t = RigidTool::cylinder("c", 0.1, 0.0, 1.0, true);
  t.axial_schedule = s;
  t.angular_schedule = PiecewiseLinear({{0.0, 1.0}});
  double time = 0.0;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.001, 0.037);
  while (time < 4.0) {
    const double dt = u(rng);
    t.begin_step(time, dt);
    t.advance(dt);
    time += dt;
  }
  EXPECT_NEAR(t.axial_offset_m, s.integral(0.0, time), 1e-12);  // sum of ~200 steps: round-off
  EXPECT_NEAR(t.angle_rad, time, 1e-12);
  EXPECT_THROW(PiecewiseLinear({{1.0, 0.0}, {0.5, 2.0}}), std::invalid_argument);  // time runs back
}

TEST(Tools, SurfacesForOutput) {
  const RigidTool plane = RigidTool::plane("p", Vec(0, 0, 1), Vec(0, 0, 1), 0.5);
  const SurfaceMesh pm = plane.surface(16);
  ASSERT_EQ(pm.polygon_count(), 2u);
  // Triangles face the workpiece (+z here).
  const Vec a = pm.points[pm.connectivity[0]], b = pm.points[pm.connectivity[1]], c = pm.points[pm.connectivity[2]];
  EXPECT_GT((b - a).cross(c - a).z(), 0.0);
  RigidTool box = RigidTool::stl("box", kBoxStl, 1e-3);
  box.axial_offset_m = 1.0;
  const SurfaceMesh bm = box.surface(16);
  EXPECT_EQ(bm.polygon_count(), 12u);
  EXPECT_EQ(bm.points.size(), 8u);  // coincident STL vertices merged
  for (const Vec& p : bm.points) EXPECT_NEAR(std::abs(p.z() - 1.0), 0.005, kExact);
  // A filleted profile: its arc drawn with points on the arc.
  const RigidTool die("die", ToolProfile({{0.03, -0.006}, {0.01, -0.006}, {0.01, 0.0}, {0.03, 0.0}}).with_fillets(0.002, {2}));
  const SurfaceMesh dm = die.surface(8);
  EXPECT_GT(dm.points.size(), 4u * 8u);
  for (const Vec& p : dm.points) {
    Vec n;
    EXPECT_NEAR(die.signed_distance(p, n), 0.0, kExact);
  }
}
