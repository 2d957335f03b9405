// ToolProfile: open (r, z) profiles of line segments and exact fillet arcs; docs/theory.md
// eqs. (40)-(42).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sphforge/tool.hpp"

namespace sphforge {

namespace {

Eigen::Vector2d left_normal(const Eigen::Vector2d& d) { return Eigen::Vector2d(-d.y(), d.x()).normalized(); }

/// Outward (workpiece-side) normal of an arc at its point p: the workpiece is on the left of the
/// walking direction, i.e. towards the centre on a counter-clockwise arc (eq. 41).
Eigen::Vector2d arc_normal(const ProfileSegment& s, const Eigen::Vector2d& p) {
  const Eigen::Vector2d radial = (p - s.centre) / s.radius;
  return s.sweep > 0.0 ? Eigen::Vector2d(-radial) : radial;
}

/// Angle wrapped into [0, 2 pi).
double wrap(double a) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  a = std::fmod(a, two_pi);
  return a < 0.0 ? a + two_pi : a;
}

}  // namespace

ToolProfile::ToolProfile(std::vector<Eigen::Vector2d> vertices) {
  if (vertices.size() < 2) throw std::invalid_argument("tool profile needs at least 2 points");
  for (const auto& p : vertices)
    if (!(p.x() >= 0.0)) throw std::invalid_argument("tool profile radius must be >= 0");
  // Drop zero-length pieces: they have no normal.
  vertices_.push_back(vertices.front());
  for (std::size_t i = 1; i < vertices.size(); ++i)
    if ((vertices[i] - vertices_.back()).norm() > 1e-12 * (1.0 + vertices[i].norm())) vertices_.push_back(vertices[i]);
  if (vertices_.size() < 2) throw std::invalid_argument("tool profile has zero length");
  fillet_.assign(vertices_.size(), 0.0);
  build();
}

ToolProfile ToolProfile::with_fillets(double radius, const std::vector<std::size_t>& corners) const {
  if (!(radius >= 0.0)) throw std::invalid_argument("fillet radius must be >= 0");
  ToolProfile out = *this;
  const std::size_t n = vertices_.size();
  if (corners.empty()) {
    for (std::size_t i = 1; i + 1 < n; ++i) out.fillet_[i] = radius;
  } else {
    for (std::size_t i : corners) {
      if (i == 0 || i + 1 >= n)
        throw std::invalid_argument("fillet corner " + std::to_string(i) + " is not an interior vertex of the profile");
      out.fillet_[i] = radius;
    }
  }
  out.build();
  return out;
}

void ToolProfile::build() {
  const std::size_t n = vertices_.size();
  const auto& V = vertices_;
  // Tangent arc at each filleted corner (eq. 41): turn angle alpha between the two directions,
  // tangent length t = R tan(alpha/2) from the corner along each segment, centre at distance R
  // from both segments on the inner side of the turn.
  std::vector<ProfileSegment> corner_arc(n);
  std::vector<double> trim(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double R = fillet_[i];
    if (R <= 0.0) continue;
    const Eigen::Vector2d u1 = (V[i] - V[i - 1]).normalized(), u2 = (V[i + 1] - V[i]).normalized();
    const double cross = u1.x() * u2.y() - u1.y() * u2.x();
    const double alpha = std::atan2(std::abs(cross), u1.dot(u2));
    if (alpha < 1e-9) continue;  // straight on: nothing to round
    if (alpha > std::numbers::pi - 1e-6)
      throw std::invalid_argument("profile vertex " + std::to_string(i) + " turns back on itself; it cannot be filleted");
    const double t = R * std::tan(0.5 * alpha);
    ProfileSegment s;
    s.arc = true;
    s.a = V[i] - t * u1;
    s.b = V[i] + t * u2;
    s.radius = R;
    s.centre = s.a + (cross > 0.0 ? 1.0 : -1.0) * R * Eigen::Vector2d(-u1.y(), u1.x());
    s.angle0 = std::atan2(s.a.y() - s.centre.y(), s.a.x() - s.centre.x());
    s.sweep = cross > 0.0 ? alpha : -alpha;
    corner_arc[i] = s;
    trim[i] = t;
  }
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double length = (V[i + 1] - V[i]).norm();
    if (trim[i] + trim[i + 1] > length * (1.0 + 1e-12))
      throw std::invalid_argument("fillets at profile vertices " + std::to_string(i) + " and " + std::to_string(i + 1) +
                                  " need " + std::to_string(trim[i] + trim[i + 1]) + " m of a segment " +
                                  std::to_string(length) + " m long");
  }

  segments_.clear();
  Eigen::Vector2d cursor = V[0];
  auto add_line = [&](const Eigen::Vector2d& to) {
    if ((to - cursor).norm() <= 1e-12 * (1.0 + to.norm())) return;
    ProfileSegment s;
    s.a = cursor;
    s.b = to;
    segments_.push_back(s);
    cursor = to;
  };
  for (std::size_t i = 1; i < n; ++i) {
    if (corner_arc[i].arc) {
      add_line(corner_arc[i].a);
      segments_.push_back(corner_arc[i]);
      cursor = corner_arc[i].b;
    } else {
      add_line(V[i]);
    }
  }
  for (const auto& s : segments_)
    if (s.arc && s.centre.x() - s.radius < -1e-12 * s.radius) {
      // The arc's lowest radius: only matters when the arc's angular range covers the -r direction.
      const double rel = s.sweep > 0.0 ? wrap(std::numbers::pi - s.angle0) : wrap(s.angle0 - std::numbers::pi);
      if (rel <= std::abs(s.sweep)) throw std::invalid_argument("a fillet of the tool profile crosses the axis r = 0");
    }

  const std::size_t ns = segments_.size();
  start_normal_.resize(ns);
  end_normal_.resize(ns);
  for (std::size_t k = 0; k < ns; ++k) {
    const ProfileSegment& s = segments_[k];
    if (s.arc) {
      start_normal_[k] = arc_normal(s, s.a);
      end_normal_[k] = arc_normal(s, s.b);
    } else {
      start_normal_[k] = end_normal_[k] = left_normal(s.b - s.a);
    }
  }
  // Pseudo-normal at each joint: the mean of the two adjacent normals. Its sign test is exact
  // for points whose nearest feature is the joint (Baerentzen & Aanaes 2005, in 2D), eq. (42).
  joint_normal_.resize(ns + 1);
  joint_normal_.front() = start_normal_.front();
  joint_normal_.back() = end_normal_.back();
  for (std::size_t k = 1; k < ns; ++k) {
    const Eigen::Vector2d m = end_normal_[k - 1] + start_normal_[k];
    joint_normal_[k] = m.norm() > 1e-12 ? Eigen::Vector2d(m.normalized()) : start_normal_[k];
  }
}

double ToolProfile::signed_distance(const Eigen::Vector2d& q, Eigen::Vector2d& normal) const {
  double best_d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_point = segments_.front().a, best_normal = joint_normal_.front();
  for (std::size_t k = 0; k < segments_.size(); ++k) {
    const ProfileSegment& s = segments_[k];
    Eigen::Vector2d p, nf;
    if (!s.arc) {
      // Nearest point of a segment (eq. 40): the clamped projection.
      const Eigen::Vector2d d = s.b - s.a;
      const double t = std::clamp((q - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      p = s.a + t * d;
      nf = t <= 0.0 ? joint_normal_[k] : (t >= 1.0 ? joint_normal_[k + 1] : start_normal_[k]);
    } else {
      // Nearest point of an arc (eq. 41): the radial projection when q's angle about the centre
      // lies within the sweep, else the nearer end.
      const Eigen::Vector2d w = q - s.centre;
      const double rho = w.norm();
      const double phi = std::atan2(w.y(), w.x());
      const double rel = s.sweep > 0.0 ? wrap(phi - s.angle0) : wrap(s.angle0 - phi);
      if (rho > 1e-300 && rel <= std::abs(s.sweep)) {
        p = s.centre + s.radius * w / rho;
        nf = arc_normal(s, p);
      } else if (rho <= 1e-300) {  // at the centre: every point of the arc is nearest; take the middle
        const double mid = s.angle0 + 0.5 * s.sweep;
        p = s.centre + s.radius * Eigen::Vector2d(std::cos(mid), std::sin(mid));
        nf = arc_normal(s, p);
      } else if ((q - s.a).squaredNorm() <= (q - s.b).squaredNorm()) {
        p = s.a;
        nf = joint_normal_[k];
      } else {
        p = s.b;
        nf = joint_normal_[k + 1];
      }
    }
    const double d2 = (q - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best_point = p;
      best_normal = nf;
    }
  }
  const Eigen::Vector2d diff = q - best_point;
  const double dist = std::sqrt(best_d2);
  const double sign = diff.dot(best_normal) >= 0.0 ? 1.0 : -1.0;
  normal = dist > 1e-14 ? Eigen::Vector2d(sign * diff / dist) : best_normal;
  return sign * dist;
}

std::vector<Eigen::Vector2d> ToolProfile::sample(double max_turn_rad) const {
  std::vector<Eigen::Vector2d> points{segments_.front().a};
  for (const ProfileSegment& s : segments_) {
    if (s.arc) {
      const int n = std::max(1, static_cast<int>(std::ceil(std::abs(s.sweep) / std::max(max_turn_rad, 1e-6))));
      for (int i = 1; i < n; ++i) {
        const double a = s.angle0 + s.sweep * i / n;
        points.emplace_back(std::max(0.0, s.centre.x() + s.radius * std::cos(a)), s.centre.y() + s.radius * std::sin(a));
      }
    }
    points.push_back(s.b);
  }
  return points;
}

}  // namespace sphforge
