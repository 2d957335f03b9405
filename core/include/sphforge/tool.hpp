// Rigid tools: analytic surfaces of revolution about the global z axis.
//
// A tool's shape is an open polyline in the (r, z) half-plane, revolved about the z axis.
// Orientation convention: walking along the polyline, the workpiece is on the LEFT, i.e. the
// outward normal (into the workpiece) of a segment with direction (dr, dz) is (-dz, dr)/len.
// Examples: barrel wall r = R0 walked upwards; a ram face at z = z0 walked from r = R0 to r = 0.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace sphforge {

class RigidTool {
 public:
  RigidTool(std::string name, std::vector<Eigen::Vector2d> profile_rz);

  /// Appends a circular arc (fillet) from the current last vertex to `end`, with centre `centre`
  /// in (r, z), approximated by chords whose sagitta stays below `max_sagitta` (m).
  static std::vector<Eigen::Vector2d> arc(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                          const Eigen::Vector2d& centre, double max_sagitta);

  const std::string& name() const { return name_; }
  const std::vector<Eigen::Vector2d>& profile() const { return profile_; }

  /// Signed distance (m) from world point x to the surface in its current pose, positive on
  /// the workpiece side, and the unit normal pointing into the workpiece side.
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const;

  /// Velocity of the tool's material point at world point x (translation along z + rotation about z).
  Eigen::Vector3d surface_velocity(const Eigen::Vector3d& x) const;

  /// Axis-aligned bounds (world) of the revolved surface, for culling contact candidates.
  void bounds(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const;

  // Kinematics, set by the process (from commands) and integrated by the core.
  double axial_offset_m = 0.0;       ///< current translation along z
  double axial_velocity_m_s = 0.0;   ///< along +z
  double angle_rad = 0.0;            ///< current rotation about z
  double angular_velocity_rad_s = 0.0;  ///< about +z (right-hand rule)

  // Reactions accumulated by the contact pass during the last step (force ON the tool).
  Eigen::Vector3d reaction_force_N = Eigen::Vector3d::Zero();
  double reaction_torque_Nm = 0.0;   ///< about +z
  double power_W = 0.0;              ///< power the tool delivered to the workpiece in the last step
  double work_J = 0.0;               ///< accumulated work delivered to the workpiece

  /// Advances the pose by dt with the current velocities.
  void advance(double dt) {
    axial_offset_m += axial_velocity_m_s * dt;
    angle_rad += angular_velocity_rad_s * dt;
  }

 private:
  std::string name_;
  std::vector<Eigen::Vector2d> profile_;
  std::vector<Eigen::Vector2d> segment_normal_;  // outward (workpiece side) unit normals
  std::vector<Eigen::Vector2d> vertex_normal_;   // pseudo-normals at vertices (sign at corners)
};

}  // namespace sphforge
