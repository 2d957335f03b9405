// Die families of the ram_extrusion process (plugins/processes/ram_extrusion/die_geometry.hpp):
// end points, tangency, arc radii and cone angles; docs/theory.md eqs. (80)-(86).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "processes/ram_extrusion/die_geometry.hpp"

namespace re = sphforge::ram_extrusion;
using sphforge::ProfileSegment;
using sphforge::ToolProfile;

namespace {

constexpr double mm = 1e-3;
constexpr double R0 = 14 * mm, rd = 8 * mm;  // dry-ice dies: D = 28 mm, d = 16 mm
constexpr double deg = std::numbers::pi / 180.0;
// Geometry is computed in double precision from exact formulas: 1e-12 m (1e-9 of a 1 mm feature)
// only absorbs floating-point rounding.
constexpr double kExact = 1e-12;

std::vector<ProfileSegment> arcs(const ToolProfile& p) {
  std::vector<ProfileSegment> out;
  for (const auto& s : p.segments())
    if (s.arc) out.push_back(s);
  return out;
}

// Unit tangent of an arc at one of its points (walking direction).
Eigen::Vector2d arc_tangent(const ProfileSegment& s, const Eigen::Vector2d& p) {
  const Eigen::Vector2d radial = (p - s.centre).normalized();
  const Eigen::Vector2d t(-radial.y(), radial.x());
  return s.sweep > 0.0 ? t : Eigen::Vector2d(-t);
}

}  // namespace

TEST(DieGeometry, TangentArcRadiusReproducesThePaperTables) {
  // eq. (83) against dry_ice_dies.csv; the tables give R to 0.1 mm, so half a unit, 0.05 mm, is
  // their rounding (WK45: 171.75 mm printed as 171.8, exactly half a unit: 1e-9 relative slack
  // for the floating-point evaluation).
  const double table_rounding = 0.05 * mm * (1.0 + 1e-9);
  EXPECT_NEAR(re::tangent_arc_radius(6 * mm, 20 * mm), 36.3 * mm, table_rounding);    // WK20 / WP20
  EXPECT_NEAR(re::tangent_arc_radius(6 * mm, 45 * mm), 171.8 * mm, table_rounding);   // WK45 / WP45
  EXPECT_NEAR(re::tangent_arc_radius(6 * mm, 70 * mm), 411.3 * mm, table_rounding);   // WK70 / WP70
  EXPECT_NEAR(re::tangent_arc_radius(1.5 * mm, 17.5 * mm), 102.8 * mm, table_rounding);  // WKWP70-25 R1
  EXPECT_NEAR(re::tangent_arc_radius(4.5 * mm, 52.5 * mm), 308.5 * mm, table_rounding);  // WKWP70-25 R2
  EXPECT_NEAR(re::tangent_arc_radius(3.0 * mm, 35.0 * mm), 205.7 * mm, table_rounding);  // WKWP70-50
}

TEST(DieGeometry, SquareEntryIsTheFilletedPolyline) {
  const re::DieShape s = re::square_die(12.5 * mm, 1.5 * mm, 0.0, 0.3 * mm);
  EXPECT_DOUBLE_EQ(s.exit_z, -0.3 * mm);  // L = 0: the fillet's radius of land
  const ToolProfile p = s.profile(12.5 * mm);
  ASSERT_EQ(p.vertices().size(), 4u);
  EXPECT_NEAR((p.vertices()[2] - Eigen::Vector2d(1.5 * mm, 0.0)).norm(), 0.0, kExact);
  const auto a = arcs(p);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_DOUBLE_EQ(a[0].radius, 0.3 * mm);
  EXPECT_NEAR(std::abs(a[0].sweep), 0.5 * std::numbers::pi, 1e-12);  // a right-angle corner
}

TEST(DieGeometry, CsConeLengthsAndAnglesMatchTheTable) {
  // CS50..CS150: cone from R0 to d/2 at the taper angle; the table gives h to 0.01 mm.
  const double table_rounding = 0.005 * mm;
  const std::pair<double, double> table[] = {{5, 68.58}, {7.5, 45.57}, {10, 34.03}, {15, 22.39}};
  for (auto [alpha, h] : table) {
    const re::DieShape s = re::conical_die(R0, rd, alpha * deg, 0.0, 10 * mm, 0.0);
    ASSERT_EQ(s.wall.size(), 3u) << alpha;  // entry, land top, exit: no flat face
    EXPECT_NEAR(s.converging_length, h * mm, table_rounding) << alpha;
    const Eigen::Vector2d cone = s.wall[0].p - s.wall[1].p;
    EXPECT_NEAR(std::atan2(cone.x(), cone.y()), alpha * deg, 1e-12) << alpha;  // half-angle to the axis
    EXPECT_NEAR(s.wall[2].p.y(), -s.converging_length - 10 * mm, kExact);
  }
}

TEST(DieGeometry, PasteConicalInsertWithShortConeHasAFlatFace) {
  // Paste insert: 45 deg cone of height 11 mm from d = 3 mm reaches r = 12.5 mm = R0 exactly.
  const re::DieShape full = re::conical_die(12.5 * mm, 1.5 * mm, 45 * deg, 11 * mm, 12 * mm, 0.6 * mm);
  EXPECT_EQ(full.wall.size(), 3u);
  EXPECT_NEAR(full.exit_z, -23 * mm, kExact);
  // A 5 mm cone stops at r = 6.5 mm: a flat face from there to the barrel.
  const re::DieShape short_cone = re::conical_die(12.5 * mm, 1.5 * mm, 45 * deg, 5 * mm, 12 * mm, 0.6 * mm);
  ASSERT_EQ(short_cone.wall.size(), 4u);
  EXPECT_NEAR((short_cone.wall[1].p - Eigen::Vector2d(6.5 * mm, 0.0)).norm(), 0.0, kExact);
  const auto a = arcs(short_cone.profile(12.5 * mm));
  ASSERT_EQ(a.size(), 1u);  // the cone-land corner fillet
  EXPECT_NEAR(std::abs(a[0].sweep), 45 * deg, 1e-12);
  EXPECT_THROW(re::conical_die(12.5 * mm, 1.5 * mm, 45 * deg, 20 * mm, 0.0, 0.0), std::invalid_argument);
}

TEST(DieGeometry, ArcThroughTwoPointsHasItsRadiusOnTheChosenSide) {
  const Eigen::Vector2d P(R0, 0.0), Q(rd, -20 * mm);
  for (re::Bulge b : {re::Bulge::outward, re::Bulge::inward}) {
    Eigen::Vector2d c, v;
    re::arc_through(P, Q, 36.3 * mm, b, c, v);
    EXPECT_NEAR((P - c).norm(), 36.3 * mm, kExact);
    EXPECT_NEAR((Q - c).norm(), 36.3 * mm, kExact);
    // The corner of the end tangents: equally far from both ends, tangent lines perpendicular to the radii.
    EXPECT_NEAR((v - P).dot(P - c), 0.0, 1e-15);  // m^2: rounding of products of ~1e-2 m lengths
    EXPECT_NEAR((v - Q).dot(Q - c), 0.0, 1e-15);
    // The arc's middle point lies on the bulge side of the chord.
    const Eigen::Vector2d M = 0.5 * (P + Q), mid = c + 36.3 * mm * (M - c).normalized();
    if (b == re::Bulge::outward) EXPECT_GT(mid.x(), M.x());
    else EXPECT_LT(mid.x(), M.x());
  }
  Eigen::Vector2d c, v;
  EXPECT_THROW(re::arc_through(P, Q, 5 * mm, re::Bulge::outward, c, v), std::invalid_argument);  // R < chord/2
}

TEST(DieGeometry, WkConvexArcIsTangentToTheBarrelAndWpConcaveArcToTheLand) {
  for (double h : {20.0, 45.0, 70.0}) {
    const double R = re::tangent_arc_radius(6 * mm, h * mm);
    // WK: convex frustum, bulging outward, tangent to the barrel wall at the entry (eq. 83).
    const re::DieShape wk = re::spherical_die(R0, rd, {{R, h * mm, re::Bulge::outward}}, 80 * mm - h * mm);
    auto a = arcs(wk.profile(R0));
    ASSERT_EQ(a.size(), 1u);
    EXPECT_DOUBLE_EQ(a[0].radius, R);
    // The profile is walked upwards: the arc runs from the land top to the entry.
    EXPECT_NEAR((a[0].a - Eigen::Vector2d(rd, -h * mm)).norm(), 0.0, kExact) << h;
    EXPECT_NEAR((a[0].b - Eigen::Vector2d(R0, 0.0)).norm(), 0.0, kExact) << h;
    EXPECT_NEAR(std::abs(arc_tangent(a[0], a[0].b).x()), 0.0, 1e-9) << h;  // axial at the entry
    // and meets the land at 2 atan(drop / h) (a kink): twice the chord's angle to the axis.
    EXPECT_NEAR(std::asin(std::abs(arc_tangent(a[0], a[0].a).x())), 2 * std::atan(6.0 / h), 1e-9) << h;
    EXPECT_LT(a[0].centre.x(), rd);  // centre on the axis side
    EXPECT_NEAR(wk.exit_z, -80 * mm, kExact);

    // WP: concave, bulging inward, tangent to the land at the exit.
    const re::DieShape wp = re::spherical_die(R0, rd, {{R, h * mm, re::Bulge::inward}}, 80 * mm - h * mm);
    a = arcs(wp.profile(R0));
    ASSERT_EQ(a.size(), 1u);
    EXPECT_NEAR(std::abs(arc_tangent(a[0], a[0].a).x()), 0.0, 1e-9) << h;  // axial at the land
    EXPECT_NEAR(std::asin(std::abs(arc_tangent(a[0], a[0].b).x())), 2 * std::atan(6.0 / h), 1e-9) << h;
    EXPECT_GT(a[0].centre.x(), R0);  // centre outside the die
  }
}

TEST(DieGeometry, ExactArcWallGivesExactDistances) {
  // WK20 with the table radius: a point 1 mm inside the wall at z = -10 mm is 1 mm from it.
  const double R = 36.3 * mm;
  const re::DieShape wk = re::spherical_die(R0, rd, {{R, 20 * mm, re::Bulge::outward}}, 60 * mm);
  const ToolProfile p = wk.profile(R0);
  const auto a = arcs(p);
  ASSERT_EQ(a.size(), 1u);
  const double z = -10 * mm;
  const double rw = a[0].centre.x() + std::sqrt(R * R - std::pow(z - a[0].centre.y(), 2));
  const Eigen::Vector2d toward_centre = (a[0].centre - Eigen::Vector2d(rw, z)).normalized();
  Eigen::Vector2d n;
  const double d = p.signed_distance(Eigen::Vector2d(rw, z) + 1 * mm * toward_centre, n);
  EXPECT_NEAR(d, 1 * mm, kExact);  // positive: on the material side
  EXPECT_NEAR(n.dot(toward_centre), 1.0, 1e-12);
}

TEST(DieGeometry, WkwpIsAnSCurveSmoothAtTheJunction) {
  for (double a : {0.25, 0.5, 0.75}) {
    const double h1 = a * 70 * mm, h2 = (1 - a) * 70 * mm;
    const double R1 = re::tangent_arc_radius(a * 6 * mm, h1), R2 = re::tangent_arc_radius((1 - a) * 6 * mm, h2);
    const re::DieShape s = re::spherical_die(
        R0, rd, {{R1, h1, re::Bulge::outward}, {R2, h2, re::Bulge::inward}}, 10 * mm);
    const auto arc = arcs(s.profile(R0));
    ASSERT_EQ(arc.size(), 2u);
    // Walked upwards: arc[0] is the concave one (R2) from the land, arc[1] the convex one (R1).
    EXPECT_DOUBLE_EQ(arc[0].radius, R2);
    EXPECT_DOUBLE_EQ(arc[1].radius, R1);
    const Eigen::Vector2d junction(R0 - a * 6 * mm, -h1);  // eq. (84): drop shared as h1 / H' = a
    EXPECT_NEAR((arc[0].b - junction).norm(), 0.0, kExact) << a;
    EXPECT_NEAR((arc[1].a - junction).norm(), 0.0, kExact) << a;
    // Both arcs meet the junction at 2 atan(6/70) to the axis: one tangent, no kink.
    EXPECT_NEAR(arc_tangent(arc[0], arc[0].b).dot(arc_tangent(arc[1], arc[1].a)), 1.0, 1e-12) << a;
    // and the whole converging section is smooth: axial at the barrel and at the land.
    EXPECT_NEAR(std::abs(arc_tangent(arc[1], arc[1].b).x()), 0.0, 1e-9) << a;
    EXPECT_NEAR(std::abs(arc_tangent(arc[0], arc[0].a).x()), 0.0, 1e-9) << a;
    EXPECT_NEAR(s.exit_z, -80 * mm, kExact);
  }
}

TEST(DieGeometry, GeneralProfileIsCheckedAndKeepsItsFillets) {
  const re::DieShape s = re::profile_die({{{R0, 0.0}, 0.0}, {{rd, -10 * mm}, 2 * mm}, {{rd, -30 * mm}, 0.0}});
  EXPECT_DOUBLE_EQ(s.exit_radius, rd);
  EXPECT_DOUBLE_EQ(s.exit_z, -30 * mm);
  EXPECT_EQ(arcs(s.profile(R0)).size(), 1u);
  EXPECT_THROW(re::profile_die({{{R0, 0.0}, 0.0}, {{rd, 5 * mm}, 0.0}}), std::invalid_argument);  // rises
  EXPECT_THROW(re::profile_die({{{R0, 0.0}, 0.0}, {{-1 * mm, -5 * mm}, 0.0}}), std::invalid_argument);
  EXPECT_THROW(re::bulge_from_string("up"), std::invalid_argument);
}
