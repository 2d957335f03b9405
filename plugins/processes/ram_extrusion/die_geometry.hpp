// Die geometry of the ram_extrusion process: the die families (square entry, conical entry, the
// dry-ice CS / WK / WP / WKWP dies) and general profiles, as an (r, z) polyline whose corners may
// carry exact arcs (ToolProfile fillets). docs/theory.md eqs. (80)-(86); docs/processes/ram_extrusion.md "Dies".
//
// Coordinates: z is the extrusion axis, the die entry (where the die meets the barrel wall,
// r = R0) is the plane z = 0, the converging section and the land lie below it and the
// extrudate leaves downwards. Free of the plugin machinery so that it can be unit-tested.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sphforge/tool.hpp"

namespace sphforge::ram_extrusion {

/// Which side of its chord an arc of the converging section lies on, eq. (82).
/// outward: away from the axis (centre on the axis side; the cavity is a convex spherical
/// frustum, tangent to the barrel wall at the entry for radii from eq. (83));
/// inward: towards the axis (centre outside; the die wall bulges into the cavity, concave
/// frustum, tangent to the land at the exit for radii from eq. (83)).
enum class Bulge { outward, inward };
Bulge bulge_from_string(const std::string& s);  ///< "outward" | "inward"; throws std::invalid_argument

/// One vertex of a die wall walked from the entry (r = R0, z = 0) down to the exit; `fillet` > 0
/// rounds it with an exact tangent arc of that radius (eq. 41).
struct WallVertex {
  Eigen::Vector2d p;
  double fillet = 0.0;
};

/// A die: its wall from the entry to the exit (the land's lower end), exact arcs included.
struct DieShape {
  std::vector<WallVertex> wall;  ///< from (R0, 0) (or the orifice plane) down to (d/2, exit_z)
  double exit_radius = 0.0;      ///< d/2 (m)
  double exit_z = 0.0;           ///< z of the land's lower end (m), < 0
  double converging_length = 0;  ///< axial length of the converging section (m), 0 for a square entry

  /// The tool profile, walked with the material on its left: in along the underside
  /// (r from `underside_radius` to d/2 at exit_z), up the land and the converging wall to the entry.
  ToolProfile profile(double underside_radius) const;
};

/// Square (flat) entry: face z = 0 from R0 in to d/2, entry corner filleted (`fillet`), land L
/// (exit at -max(L, fillet) so that the fillet fits), eq. (80).
DieShape square_die(double R0, double d_half, double land, double fillet);

/// Conical entry, cone half-angle `angle_rad` to the axis, cone of axial height `cone_height`
/// (<= 0: the cone reaches the barrel wall, height (R0 - d/2) / tan(angle)), flat face from the
/// cone top out to R0 when the cone is shorter, land L, cone-land corner filleted, eq. (81).
/// The dry-ice CS dies are cones that reach the barrel wall.
DieShape conical_die(double R0, double d_half, double angle_rad, double cone_height, double land, double fillet);

/// The centre of the circle of radius R through the points P and Q on the `bulge` side (radius
/// direction: +r outward), and the intersection V of the arc's end tangents, eq. (82).
/// Throws std::invalid_argument when R is shorter than half the chord or the arc is a half circle.
void arc_through(const Eigen::Vector2d& P, const Eigen::Vector2d& Q, double R, Bulge bulge, Eigen::Vector2d& centre,
                 Eigen::Vector2d& corner);

/// Radius of the arc over radial drop `drop` and axial length h that is tangent to the axial
/// direction at one end: R = (drop^2 + h^2) / (2 drop), the papers' eq. (3) rewritten, eq. (83).
double tangent_arc_radius(double drop, double h);

/// One spherical section of a converging die: radius R over axial length h (m), bulging `bulge`.
struct ArcSection {
  double radius = 0.0, length = 0.0;
  Bulge bulge = Bulge::outward;
};

/// Dry-ice spherical dies (WK: one section of radius R1 over h1; WP: R2 over h2; WKWP: R1 over h1
/// then R2 over h2): the converging section is the chain of arcs, the radial drop shared in
/// proportion to the section lengths (h1 / H' = a, eq. 84), then a land of length L, eq. (85).
DieShape spherical_die(double R0, double d_half, const std::vector<ArcSection>& sections, double land);

/// A general wall from (r, z) vertices walked downwards from the entry, each optionally
/// filleted; the last vertex is the exit (its z < 0, r = d/2). eq. (86). Throws
/// std::invalid_argument for r < 0, z rising along the wall, or a last vertex at z >= 0.
DieShape profile_die(std::vector<WallVertex> wall);

}  // namespace sphforge::ram_extrusion
