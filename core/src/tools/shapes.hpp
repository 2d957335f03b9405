// Internal shapes of the rigid tools that need more than the public header (the STL mesh).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sphforge/tool.hpp"

namespace sphforge {

/// Reads an STL file (vtkSTLReader, coincident points merged) scaled by `scale` into a mesh shape
/// with a bounding-volume hierarchy; throws std::runtime_error when unreadable or empty.
std::shared_ptr<const ToolShape> load_stl_shape(const std::string& path, double scale);

/// A closed triangle mesh (outward normals: the workpiece outside), eq. (44).
std::shared_ptr<const ToolShape> make_mesh_shape(std::vector<Eigen::Vector3d> points,
                                                 std::vector<std::array<int, 3>> triangles);

/// Brute-force signed distance of the same mesh (every triangle), for testing the hierarchy.
double mesh_signed_distance_brute_force(const ToolShape& mesh, const Eigen::Vector3d& x, Eigen::Vector3d& normal);

}  // namespace sphforge
