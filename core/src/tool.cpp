#include "sphforge/tool.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace sphforge {

namespace {
Eigen::Vector2d left_normal(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  return Eigen::Vector2d(-d.y(), d.x()).normalized();
}
}  // namespace

RigidTool::RigidTool(std::string name, std::vector<Eigen::Vector2d> profile_rz)
    : name_(std::move(name)), profile_(std::move(profile_rz)) {
  if (profile_.size() < 2) throw std::invalid_argument("tool '" + name_ + "': profile needs at least 2 points");
  // Drop zero-length segments: they have no normal.
  std::vector<Eigen::Vector2d> cleaned{profile_.front()};
  for (std::size_t i = 1; i < profile_.size(); ++i)
    if ((profile_[i] - cleaned.back()).norm() > 1e-12 * (1.0 + profile_[i].norm())) cleaned.push_back(profile_[i]);
  profile_ = std::move(cleaned);
  if (profile_.size() < 2) throw std::invalid_argument("tool '" + name_ + "': profile has zero length");
  for (const auto& p : profile_)
    if (p.x() < 0.0) throw std::invalid_argument("tool '" + name_ + "': profile radius must be >= 0");

  const std::size_t nseg = profile_.size() - 1;
  segment_normal_.resize(nseg);
  for (std::size_t s = 0; s < nseg; ++s) segment_normal_[s] = left_normal(profile_[s], profile_[s + 1]);
  // Pseudo-normal at each vertex: the mean of the adjacent segment normals. Its sign test is
  // exact for points whose nearest feature is the vertex (Baerentzen & Aanaes 2005, in 2D).
  vertex_normal_.resize(profile_.size());
  vertex_normal_.front() = segment_normal_.front();
  vertex_normal_.back() = segment_normal_.back();
  for (std::size_t v = 1; v + 1 < profile_.size(); ++v) {
    Eigen::Vector2d n = segment_normal_[v - 1] + segment_normal_[v];
    vertex_normal_[v] = n.norm() > 1e-12 ? n.normalized() : segment_normal_[v];
  }
}

std::vector<Eigen::Vector2d> RigidTool::arc(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                            const Eigen::Vector2d& centre, double max_sagitta) {
  const double radius = (start - centre).norm();
  double a0 = std::atan2(start.y() - centre.y(), start.x() - centre.x());
  double a1 = std::atan2(end.y() - centre.y(), end.x() - centre.x());
  // Take the shorter way round (fillets are always less than half a turn).
  double sweep = a1 - a0;
  while (sweep > std::numbers::pi) sweep -= 2 * std::numbers::pi;
  while (sweep < -std::numbers::pi) sweep += 2 * std::numbers::pi;
  // Sagitta of a chord spanning angle t: r (1 - cos(t/2)) <= max_sagitta.
  const double max_step = 2.0 * std::acos(std::clamp(1.0 - max_sagitta / radius, -1.0, 1.0));
  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(sweep) / std::max(max_step, 1e-6))));
  std::vector<Eigen::Vector2d> points;
  for (int i = 1; i <= n; ++i) {
    const double a = a0 + sweep * i / n;
    points.emplace_back(centre.x() + radius * std::cos(a), centre.y() + radius * std::sin(a));
  }
  points.back() = end;
  return points;
}

double RigidTool::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const {
  // Work in the tool's frame: (r, z - offset). Rotation about z does not change r or z.
  const double r = std::hypot(x.x(), x.y());
  const Eigen::Vector2d q(r, x.z() - axial_offset_m);

  double best_d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_point = profile_.front();
  Eigen::Vector2d best_sign_normal = segment_normal_.front();
  for (std::size_t s = 0; s + 1 < profile_.size(); ++s) {
    const Eigen::Vector2d a = profile_[s], d = profile_[s + 1] - a;
    const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const Eigen::Vector2d p = a + t * d;
    const double d2 = (q - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best_point = p;
      best_sign_normal = t <= 0.0 ? vertex_normal_[s] : (t >= 1.0 ? vertex_normal_[s + 1] : segment_normal_[s]);
    }
  }
  const Eigen::Vector2d diff = q - best_point;
  const double dist = std::sqrt(best_d2);
  const double sign = diff.dot(best_sign_normal) >= 0.0 ? 1.0 : -1.0;
  Eigen::Vector2d n2 = dist > 1e-14 ? Eigen::Vector2d(sign * diff / dist) : best_sign_normal;

  // Back to 3D: e_r is undefined on the axis; any radial direction serves there.
  const Eigen::Vector3d e_r = r > 1e-14 ? Eigen::Vector3d(x.x() / r, x.y() / r, 0.0) : Eigen::Vector3d(1, 0, 0);
  normal = n2.x() * e_r + Eigen::Vector3d(0, 0, n2.y());
  return sign * dist;
}

Eigen::Vector3d RigidTool::surface_velocity(const Eigen::Vector3d& x) const {
  // v = v_z e_z + omega e_z x (x - axis point); the axis is the global z axis.
  return Eigen::Vector3d(-angular_velocity_rad_s * x.y(), angular_velocity_rad_s * x.x(), axial_velocity_m_s);
}

void RigidTool::bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
  double rmax = 0.0, zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  for (const auto& p : profile_) {
    rmax = std::max(rmax, p.x());
    zmin = std::min(zmin, p.y());
    zmax = std::max(zmax, p.y());
  }
  lo = Eigen::Vector3d(-rmax, -rmax, zmin + axial_offset_m);
  hi = Eigen::Vector3d(rmax, rmax, zmax + axial_offset_m);
}

}  // namespace sphforge
