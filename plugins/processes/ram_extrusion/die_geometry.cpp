// Die geometry of the ram_extrusion process; docs/theory.md eqs. (80)-(86).
#include "die_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sphforge::ram_extrusion {

Bulge bulge_from_string(const std::string& s) {
  if (s == "outward") return Bulge::outward;
  if (s == "inward") return Bulge::inward;
  throw std::invalid_argument("arc bulge must be 'outward' or 'inward', not '" + s + "'");
}

ToolProfile DieShape::profile(double underside_radius) const {
  // Walked with the material on the left (docs/theory.md eq. 42): in along the underside, so that
  // extrudate swelling below the exit is outside the die, then up the wall to the entry.
  std::vector<Eigen::Vector2d> v{{underside_radius, exit_z}};
  std::vector<double> fillet{0.0};
  for (auto it = wall.rbegin(); it != wall.rend(); ++it) {
    v.push_back(it->p);
    fillet.push_back(it->fillet);
  }
  ToolProfile out(v);
  // Each rounded corner gets its own radius (the WKWP dies have two); indices are those of `v`,
  // which ToolProfile keeps because the die walls have no zero-length pieces.
  if (out.vertices().size() != v.size()) throw std::invalid_argument("die wall has coincident vertices");
  for (std::size_t i = 1; i + 1 < v.size(); ++i)
    if (fillet[i] > 0.0) out = out.with_fillets(fillet[i], {i});
  return out;
}

DieShape square_die(double R0, double d_half, double land, double fillet) {
  if (!(d_half > 0.0 && d_half + fillet < R0)) throw std::invalid_argument("square die: need 0 < d/2 and d/2 + fillet < R0");
  DieShape s;
  s.exit_radius = d_half;
  s.exit_z = -std::max(land, fillet);  // eq. (80): the fillet needs its radius of land below the face
  s.wall = {{{R0, 0.0}, 0.0}, {{d_half, 0.0}, fillet}, {{d_half, s.exit_z}, 0.0}};
  return s;
}

DieShape conical_die(double R0, double d_half, double angle_rad, double cone_height, double land, double fillet) {
  if (!(d_half > 0.0 && d_half < R0)) throw std::invalid_argument("conical die: need 0 < d/2 < R0");
  if (!(angle_rad > 0.0 && angle_rad < 0.5 * 3.141592653589793))
    throw std::invalid_argument("conical die: the cone half-angle must lie between 0 and 90 degrees");
  const double t = std::tan(angle_rad);
  // eq. (81): the cone rises from the land top (d/2, -h_c) at the half-angle to radius d/2 + h_c tan(theta).
  const double hc = cone_height > 0.0 ? cone_height : (R0 - d_half) / t;
  const double rc = d_half + hc * t;
  if (rc > R0 * (1.0 + 1e-9)) throw std::invalid_argument("conical die: the cone is wider than the barrel at the die entry");
  DieShape s;
  s.exit_radius = d_half;
  s.converging_length = hc;
  // The fillet on the cone-land corner trims R tan(theta/2) <= R of the land: keep at least R of land.
  s.exit_z = -hc - std::max(land, fillet);
  s.wall.push_back({{R0, 0.0}, 0.0});
  if (rc < R0 * (1.0 - 1e-9)) s.wall.push_back({{rc, 0.0}, 0.0});  // flat face of the insert outside the cone
  s.wall.push_back({{d_half, -hc}, fillet});
  s.wall.push_back({{d_half, s.exit_z}, 0.0});
  return s;
}

void arc_through(const Eigen::Vector2d& P, const Eigen::Vector2d& Q, double R, Bulge bulge, Eigen::Vector2d& centre,
                 Eigen::Vector2d& corner) {
  // eq. (82): chord midpoint M, half chord a, centre at distance s = sqrt(R^2 - a^2) from M along
  // the chord normal, on the side opposite to the bulge (a minor arc bulges away from its centre).
  const Eigen::Vector2d M = 0.5 * (P + Q);
  const double c = (Q - P).norm();
  const double a = 0.5 * c;
  if (!(R > a)) throw std::invalid_argument("arc radius " + std::to_string(R) + " m is shorter than half its chord " + std::to_string(a) + " m");
  const double s = std::sqrt(R * R - a * a);
  if (s < 1e-9 * R) throw std::invalid_argument("a half-circle arc has parallel end tangents");
  Eigen::Vector2d n(-(Q - P).y() / c, (Q - P).x() / c);
  if (n.x() < 0.0) n = -n;  // n points away from the axis (+r)
  centre = bulge == Bulge::outward ? Eigen::Vector2d(M - s * n) : Eigen::Vector2d(M + s * n);
  // The end tangents meet on the line from the centre through M, at R / cos(sweep/2) = R^2 / s from the centre.
  corner = centre + (R * R / (s * s)) * (M - centre);
}

double tangent_arc_radius(double drop, double h) { return (drop * drop + h * h) / (2.0 * drop); }

DieShape spherical_die(double R0, double d_half, const std::vector<ArcSection>& sections, double land) {
  if (!(d_half > 0.0 && d_half < R0)) throw std::invalid_argument("spherical die: need 0 < d/2 < R0");
  if (sections.empty()) throw std::invalid_argument("spherical die: no arc section");
  double H = 0.0;
  for (const auto& a : sections) {
    if (!(a.length > 0.0 && a.radius > 0.0)) throw std::invalid_argument("spherical die: arc radius and length must be > 0");
    H += a.length;
  }
  DieShape s;
  s.exit_radius = d_half;
  s.converging_length = H;
  s.exit_z = -H - land;
  s.wall.push_back({{R0, 0.0}, 0.0});
  Eigen::Vector2d top(R0, 0.0);
  for (const auto& a : sections) {
    // eq. (84): each section takes the share h_k / H' of the radial drop R0 - d/2.
    const Eigen::Vector2d bottom(top.x() - (R0 - d_half) * a.length / H, top.y() - a.length);
    Eigen::Vector2d centre, corner;
    arc_through(top, bottom, a.radius, a.bulge, centre, corner);
    // An arc is the fillet of radius R of the corner where its two end tangents meet (eq. 41),
    // so the polyline top -> corner -> bottom with that corner rounded is the arc, exactly.
    s.wall.push_back({corner, a.radius});
    s.wall.push_back({bottom, 0.0});
    top = bottom;
  }
  s.wall.back().p = Eigen::Vector2d(d_half, -H);
  if (land > 0.0) s.wall.push_back({{d_half, s.exit_z}, 0.0});
  return s;
}

DieShape profile_die(std::vector<WallVertex> wall) {
  if (wall.size() < 2) throw std::invalid_argument("die profile needs at least 2 points");
  for (std::size_t i = 0; i < wall.size(); ++i) {
    if (!(wall[i].p.x() >= 0.0)) throw std::invalid_argument("die profile point " + std::to_string(i) + " has r < 0");
    if (i > 0 && wall[i].p.y() > wall[i - 1].p.y())
      throw std::invalid_argument("die profile point " + std::to_string(i) + " lies above the previous one (walk it downwards)");
  }
  DieShape s;
  s.exit_radius = wall.back().p.x();
  s.exit_z = wall.back().p.y();
  if (!(s.exit_z < 0.0)) throw std::invalid_argument("die profile must end below the die entry plane z = 0");
  s.wall = std::move(wall);
  return s;
}

}  // namespace sphforge::ram_extrusion
