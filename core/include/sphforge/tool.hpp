// Rigid tools: analytic surfaces (plane, cylinder, bodies of revolution with exact fillet arcs)
// and triangle meshes read from STL, each with a prescribed or commanded motion along and about
// the tool axis (the global z axis). Equations: docs/theory.md section 3.1, eqs. (40)-(46).
//
// Sign convention for every shape: the signed distance is positive on the workpiece side and
// the normal points into the workpiece side (for a point inside the tool: from the point towards
// the nearest surface point, i.e. the direction that pushes it out).
//
// Profiles of revolution live in the (r, z) half-plane r >= 0 and are revolved about z. Walking
// along the profile, the workpiece is on the LEFT: the outward normal of a segment with
// direction (dr, dz) is (-dz, dr)/len. Examples: barrel wall r = R0 walked upwards; a ram face
// at z = z0 walked from r = R0 to r = 0.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sphforge/piecewise_linear.hpp"

namespace sphforge {

/// One piece of a profile: a straight segment a -> b, or an exact circular arc a -> b about
/// `centre` (signed `sweep`, > 0 counter-clockwise in the (r, z) plane), eq. (41).
struct ProfileSegment {
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
  bool arc = false;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0, angle0 = 0.0, sweep = 0.0;
};

/// An open profile in the (r, z) half-plane: a polyline whose chosen corners may be rounded by
/// tangent circular arcs (fillets). Distances to it are exact (no chords), eqs. (40)-(42).
class ToolProfile {
 public:
  ToolProfile() = default;
  /// A polyline through `vertices` (r >= 0); zero-length pieces are dropped. Throws
  /// std::invalid_argument for fewer than two distinct points or a negative radius.
  explicit ToolProfile(std::vector<Eigen::Vector2d> vertices);

  /// The same polyline with the interior vertices `corners` (indices into vertices(); empty:
  /// every interior corner) rounded by tangent arcs of `radius` (m). Throws
  /// std::invalid_argument when a fillet does not fit on its two segments.
  ToolProfile with_fillets(double radius, const std::vector<std::size_t>& corners = {}) const;

  const std::vector<Eigen::Vector2d>& vertices() const { return vertices_; }
  const std::vector<ProfileSegment>& segments() const { return segments_; }

  /// Signed distance from q = (r, z) to the profile and the unit normal (workpiece side) in
  /// (r, z), eq. (42).
  double signed_distance(const Eigen::Vector2d& q, Eigen::Vector2d& normal) const;

  /// Points along the profile for drawing: every segment end, arcs subdivided so that no step
  /// turns more than `max_turn_rad`.
  std::vector<Eigen::Vector2d> sample(double max_turn_rad) const;

 private:
  void build();
  std::vector<Eigen::Vector2d> vertices_;
  std::vector<double> fillet_;                   // per vertex, 0: sharp
  std::vector<ProfileSegment> segments_;
  std::vector<Eigen::Vector2d> start_normal_, end_normal_;  // per segment, at a and at b
  std::vector<Eigen::Vector2d> joint_normal_;    // pseudo-normal at each segment start (sign at corners)
};

/// A tool surface as polygons (triangles or quads), for output.
struct SurfaceMesh {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::int64_t> offsets{0};   ///< polygon p uses connectivity[offsets[p], offsets[p+1])
  std::vector<std::int64_t> connectivity;
  void add_polygon(std::initializer_list<std::int64_t> ids) {
    connectivity.insert(connectivity.end(), ids.begin(), ids.end());
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  std::size_t polygon_count() const { return offsets.size() - 1; }
};

/// A tool's shape in its own (body) frame. Called once per batch of points, never per point
/// in a hot loop: implementations loop over the batch themselves.
class ToolShape {
 public:
  virtual ~ToolShape() = default;
  virtual const char* kind() const = 0;
  /// Signed distances d[i] and unit normals n[3i..3i+2] of the `count` body-frame points
  /// x[3i..3i+2]. Must be thread-safe (const, no shared scratch).
  virtual void signed_distance(std::size_t count, const double* x, double* d, double* n) const = 0;
  /// Body-frame axis-aligned bounds of the part of the surface that acts.
  virtual void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const = 0;
  /// The surface in the body frame; `segments` angular steps for surfaces of revolution.
  virtual void surface(SurfaceMesh& mesh, int segments) const = 0;
  /// True when a rotation about z leaves the shape unchanged (bounds need no rotation).
  virtual bool axisymmetric() const { return false; }
};

class RigidTool {
 public:
  /// A body of revolution from a polyline profile (no fillets).
  RigidTool(std::string name, std::vector<Eigen::Vector2d> profile_rz);
  RigidTool(std::string name, const ToolProfile& profile);
  RigidTool(std::string name, std::shared_ptr<const ToolShape> shape);

  /// Plane through `point` with unit normal `normal` (towards the workpiece); it acts over the
  /// square of half-width `half_size` about `point` (culling and output), eq. (43).
  static RigidTool plane(std::string name, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                         double half_size);
  /// Cylinder r = radius for z_min <= z <= z_max; `inside`: the workpiece is inside (a barrel).
  static RigidTool cylinder(std::string name, double radius, double z_min, double z_max, bool inside);
  /// Closed triangle mesh from an ASCII or binary STL file, coordinates multiplied by `scale`
  /// (to metres); the workpiece is outside (normals of the file point out of the tool), eq. (44).
  /// Throws std::runtime_error when the file cannot be read or holds no triangle.
  static RigidTool stl(std::string name, const std::string& path, double scale = 1.0);

  const std::string& name() const { return name_; }
  const ToolShape& shape() const { return *shape_; }

  /// Signed distance (m) from world point x to the surface in its current pose, positive on
  /// the workpiece side, and the unit normal pointing into the workpiece side.
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const;

  /// Batch form: world points x[3i..], distances d[i], normals normal[3i..]. Points farther than
  /// `cutoff` outside bounds() get d = +infinity and an untouched normal (culling). OpenMP-parallel;
  /// call it from outside a parallel region.
  void signed_distance(std::size_t count, const double* x, double* d, double* normal,
                       double cutoff = std::numeric_limits<double>::infinity()) const;

  /// Velocity of the tool's material point at world point x (translation along z + rotation
  /// about z), eq. (46).
  Eigen::Vector3d surface_velocity(const Eigen::Vector3d& x) const;

  /// Axis-aligned bounds (world) of the surface in its current pose, for culling contact candidates.
  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const;

  /// The surface in world coordinates in the current pose.
  SurfaceMesh surface(int segments) const;

  // Kinematics, set by the process (from commands) or by the schedules, integrated by the core.
  double axial_offset_m = 0.0;       ///< current translation along z
  double axial_velocity_m_s = 0.0;   ///< along +z
  double angle_rad = 0.0;            ///< current rotation about z
  double angular_velocity_rad_s = 0.0;  ///< about +z (right-hand rule)
  /// Prescribed schedules of axial velocity (m/s) and angular velocity (rad/s) against time;
  /// when set, begin_step() overrides the velocity the process set.
  PiecewiseLinear axial_schedule, angular_schedule;

  // Reactions accumulated by the contact pass during the last step (force ON the tool).
  Eigen::Vector3d reaction_force_N = Eigen::Vector3d::Zero();
  double reaction_torque_Nm = 0.0;   ///< about +z
  double power_W = 0.0;              ///< power the tool delivered to the workpiece in the last step
  double friction_heat_W = 0.0;      ///< sum |f_t| |v_t| over its contacts in the last step (eq. 18e)
  double work_J = 0.0;               ///< accumulated work delivered to the workpiece

  /// Called by the core at the start of a step [t, t + dt]: a scheduled velocity becomes the
  /// schedule's mean over the step, so that advance() lands exactly on its integral (eq. 45).
  void begin_step(double t, double dt);

  /// Advances the pose by dt with the current velocities.
  void advance(double dt) {
    axial_offset_m += axial_velocity_m_s * dt;
    angle_rad += angular_velocity_rad_s * dt;
  }

 private:
  std::string name_;
  std::shared_ptr<const ToolShape> shape_;
};

}  // namespace sphforge
