// RigidTool: pose, kinematics and the analytic shapes (plane, cylinder, body of revolution);
// docs/theory.md eqs. (40)-(46). The STL mesh shape is in mesh.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>

#include "sphforge/tool.hpp"
#include "tools/shapes.hpp"

namespace sphforge {

namespace {

/// Body of revolution about z from an (r, z) profile (cylinders and cones are one-segment profiles).
class RevolutionShape final : public ToolShape {
 public:
  RevolutionShape(ToolProfile profile, const char* kind) : profile_(std::move(profile)), kind_(kind) {}
  const char* kind() const override { return kind_; }
  bool axisymmetric() const override { return true; }

  void signed_distance(std::size_t count, const double* x, double* d, double* n) const override {
    for (std::size_t i = 0; i < count; ++i) {
      // The distance to a surface of revolution is the distance in the meridian half-plane
      // through the point (eq. 42): the nearest point of each circle lies at the same azimuth.
      const double px = x[3 * i], py = x[3 * i + 1], r = std::hypot(px, py);
      Eigen::Vector2d n2;
      d[i] = profile_.signed_distance(Eigen::Vector2d(r, x[3 * i + 2]), n2);
      // On the axis e_r is undefined; any radial direction serves there (n2.x is 0 for a face
      // that reaches the axis, where the nearest point is unique).
      const double ex = r > 1e-14 ? px / r : 1.0, ey = r > 1e-14 ? py / r : 0.0;
      n[3 * i] = n2.x() * ex;
      n[3 * i + 1] = n2.x() * ey;
      n[3 * i + 2] = n2.y();
    }
  }

  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const override {
    // A fillet arc lies inside the triangle of its corner and its two tangent points, so the
    // polyline's vertices bound the rounded profile too.
    double rmax = 0.0, zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
    for (const auto& p : profile_.vertices()) {
      rmax = std::max(rmax, p.x());
      zmin = std::min(zmin, p.y());
      zmax = std::max(zmax, p.y());
    }
    lo = Eigen::Vector3d(-rmax, -rmax, zmin);
    hi = Eigen::Vector3d(rmax, rmax, zmax);
  }

  void surface(SurfaceMesh& mesh, int segments) const override {
    const std::size_t S = static_cast<std::size_t>(segments);
    const std::vector<Eigen::Vector2d> pts = profile_.sample(2.0 * std::numbers::pi / segments);
    const std::size_t m = pts.size();
    // Profile-major: profile point j at angle step k is j*S + k.
    for (std::size_t j = 0; j < m; ++j)
      for (std::size_t k = 0; k < S; ++k) {
        const double theta = 2.0 * std::numbers::pi * double(k) / double(S);
        mesh.points.emplace_back(pts[j].x() * std::cos(theta), pts[j].x() * std::sin(theta), pts[j].y());
      }
    // Quads (j,k) (j+1,k) (j+1,k+1) (j,k+1): their right-hand normal is (-dz, dr) in the (r, z)
    // plane, i.e. towards the workpiece. Quads at r = 0 degenerate to triangles with a repeated point.
    for (std::size_t j = 0; j + 1 < m; ++j)
      for (std::size_t k = 0; k < S; ++k) {
        const auto k1 = static_cast<std::int64_t>((k + 1) % S), kk = static_cast<std::int64_t>(k);
        const auto a = static_cast<std::int64_t>(j * S), b = static_cast<std::int64_t>((j + 1) * S);
        mesh.add_polygon({a + kk, b + kk, b + k1, a + k1});
      }
  }

 private:
  ToolProfile profile_;
  const char* kind_;
};

/// Plane through p0 with unit normal n (eq. 43), acting over a square of half-width h.
class PlaneShape final : public ToolShape {
 public:
  PlaneShape(const Eigen::Vector3d& p0, const Eigen::Vector3d& n, double h) : p0_(p0), n_(n.normalized()), h_(h) {
    // In-plane axes with u x v = n, so the output triangles face the workpiece.
    const Eigen::Vector3d helper = std::abs(n_.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
    u_ = helper.cross(n_).normalized();
    v_ = n_.cross(u_);
  }
  const char* kind() const override { return "plane"; }

  void signed_distance(std::size_t count, const double* x, double* d, double* n) const override {
    for (std::size_t i = 0; i < count; ++i) {
      d[i] = (x[3 * i] - p0_.x()) * n_.x() + (x[3 * i + 1] - p0_.y()) * n_.y() + (x[3 * i + 2] - p0_.z()) * n_.z();
      n[3 * i] = n_.x();
      n[3 * i + 1] = n_.y();
      n[3 * i + 2] = n_.z();
    }
  }

  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const override {
    // The square plus a slab of depth h behind it, so that a particle pushed into the tool
    // still feels it.
    lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (int a : {-1, 1})
      for (int b : {-1, 1})
        for (double c : {0.0, -1.0}) {
          const Eigen::Vector3d p = p0_ + h_ * (a * u_ + b * v_ + c * n_);
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
  }

  void surface(SurfaceMesh& mesh, int) const override {
    const auto base = static_cast<std::int64_t>(mesh.points.size());
    mesh.points.push_back(p0_ + h_ * (-u_ - v_));
    mesh.points.push_back(p0_ + h_ * (u_ - v_));
    mesh.points.push_back(p0_ + h_ * (u_ + v_));
    mesh.points.push_back(p0_ + h_ * (-u_ + v_));
    mesh.add_polygon({base, base + 1, base + 2});
    mesh.add_polygon({base, base + 2, base + 3});
  }

 private:
  Eigen::Vector3d p0_, n_, u_, v_;
  double h_;
};

}  // namespace

// ---------------------------------------------------------------------------------------------


// ---------------------------------------------------------------------------------------------

RigidTool::RigidTool(std::string name, std::vector<Eigen::Vector2d> profile_rz)
    : RigidTool(std::move(name), ToolProfile(std::move(profile_rz))) {}

RigidTool::RigidTool(std::string name, const ToolProfile& profile)
    : name_(std::move(name)), shape_(std::make_shared<RevolutionShape>(profile, "revolution")) {
  if (profile.segments().empty()) throw std::invalid_argument("tool '" + name_ + "': empty profile");
}

RigidTool::RigidTool(std::string name, std::shared_ptr<const ToolShape> shape)
    : name_(std::move(name)), shape_(std::move(shape)) {
  if (!shape_) throw std::invalid_argument("tool '" + name_ + "': no shape");
}

RigidTool RigidTool::plane(std::string name, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                           double half_size) {
  if (!(normal.norm() > 0.0)) throw std::invalid_argument("tool '" + name + "': plane normal must not be zero");
  if (!(half_size > 0.0)) throw std::invalid_argument("tool '" + name + "': plane half_size must be positive");
  return RigidTool(std::move(name), std::make_shared<PlaneShape>(point, normal, half_size));
}

RigidTool RigidTool::cylinder(std::string name, double radius, double z_min, double z_max, bool inside) {
  if (!(radius > 0.0)) throw std::invalid_argument("tool '" + name + "': cylinder radius must be positive");
  if (!(z_max > z_min)) throw std::invalid_argument("tool '" + name + "': cylinder needs z_max > z_min");
  // Workpiece inside: walked upwards, normal (-dz, dr) = -e_r; outside: walked downwards.
  ToolProfile profile = inside ? ToolProfile({{radius, z_min}, {radius, z_max}})
                               : ToolProfile({{radius, z_max}, {radius, z_min}});
  return RigidTool(std::move(name), std::make_shared<RevolutionShape>(profile, "cylinder"));
}

RigidTool RigidTool::stl(std::string name, const std::string& path, double scale) {
  return RigidTool(std::move(name), load_stl_shape(path, scale));
}

double RigidTool::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const {
  double d = 0.0;
  signed_distance(1, x.data(), &d, normal.data());
  return d;
}

void RigidTool::signed_distance(std::size_t count, const double* x, double* d, double* normal, double cutoff) const {
  Eigen::Vector3d lo, hi;
  bounds(lo, hi);
  const bool cull = std::isfinite(cutoff);
  lo.array() -= cutoff;
  hi.array() += cutoff;
  // Body frame (eq. 45): x_b = R_z(-theta) (x - s e_z); normals back with R_z(theta).
  const double c = std::cos(angle_rad), s = std::sin(angle_rad), offset = axial_offset_m;
  constexpr std::size_t chunk = 128;
  const std::size_t nchunks = (count + chunk - 1) / chunk;
#pragma omp parallel for schedule(dynamic, 8) if (nchunks > 1)
  for (std::size_t b = 0; b < nchunks; ++b) {
    // Fixed-size scratch on the stack: one virtual call per chunk, no allocation.
    double xb[3 * chunk], db[chunk], nb[3 * chunk];
    std::size_t index[chunk];
    std::size_t m = 0;
    const std::size_t end = std::min(count, (b + 1) * chunk);
    for (std::size_t i = b * chunk; i < end; ++i) {
      const double px = x[3 * i], py = x[3 * i + 1], pz = x[3 * i + 2];
      if (cull && (px < lo.x() || py < lo.y() || pz < lo.z() || px > hi.x() || py > hi.y() || pz > hi.z())) {
        d[i] = std::numeric_limits<double>::infinity();
        continue;
      }
      xb[3 * m] = c * px + s * py;
      xb[3 * m + 1] = -s * px + c * py;
      xb[3 * m + 2] = pz - offset;
      index[m++] = i;
    }
    if (m == 0) continue;
    shape_->signed_distance(m, xb, db, nb);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = index[k];
      d[i] = db[k];
      normal[3 * i] = c * nb[3 * k] - s * nb[3 * k + 1];
      normal[3 * i + 1] = s * nb[3 * k] + c * nb[3 * k + 1];
      normal[3 * i + 2] = nb[3 * k + 2];
    }
  }
}

Eigen::Vector3d RigidTool::surface_velocity(const Eigen::Vector3d& x) const {
  // Eq. (46): v = v_z e_z + omega e_z x x; the axis is the global z axis.
  return Eigen::Vector3d(-angular_velocity_rad_s * x.y(), angular_velocity_rad_s * x.x(), axial_velocity_m_s);
}

void RigidTool::bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
  Eigen::Vector3d blo, bhi;
  shape_->bounds(blo, bhi);
  const Eigen::Vector3d shift(0.0, 0.0, axial_offset_m);
  if (shape_->axisymmetric() || angle_rad == 0.0) {
    lo = blo + shift;
    hi = bhi + shift;
    return;
  }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p((corner & 1) ? bhi.x() : blo.x(), (corner & 2) ? bhi.y() : blo.y(),
                            (corner & 4) ? bhi.z() : blo.z());
    const Eigen::Vector3d w = R * p + shift;
    lo = lo.cwiseMin(w);
    hi = hi.cwiseMax(w);
  }
}

SurfaceMesh RigidTool::surface(int segments) const {
  SurfaceMesh mesh;
  shape_->surface(mesh, segments);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (auto& p : mesh.points) p = R * p + Eigen::Vector3d(0.0, 0.0, axial_offset_m);
  return mesh;
}

void RigidTool::begin_step(double t, double dt) {
  if (!axial_schedule.empty())
    axial_velocity_m_s = dt > 0.0 ? axial_schedule.integral(t, t + dt) / dt : axial_schedule.value(t);
  if (!angular_schedule.empty())
    angular_velocity_rad_s = dt > 0.0 ? angular_schedule.integral(t, t + dt) / dt : angular_schedule.value(t);
}

}  // namespace sphforge
