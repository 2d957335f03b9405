// Thermal-only bodies attached to a tool (docs/theory.md eq. 90, docs/contact.md "Heat into the
// tools"): their particles move rigidly with the tool's pose, placed every step from fixed
// reference positions so that no drift accumulates however many steps the run takes.
#pragma once

#include <cstddef>

#include "sphforge/tool.hpp"

namespace sphforge {

/// Field of the attached particles' positions in the tool's frame (m, 3 per particle): registered
/// so that it moves with the particles when the core reorders them.
inline constexpr const char* kToolReferencePosition = "tool_reference_position";

/// Reference (tool-frame) positions of particles at world positions x for the tool's current
/// pose: X = R_z(-theta) (x - w e_z)  (inverse of eq. 90).
void attach_to_tool(const RigidTool& tool, const double* x, double* reference, std::size_t n);

/// Places particles from their reference positions in the tool's current pose:
/// x = R_z(theta) X + w e_z  (eq. 90), theta = tool.angle_rad, w = tool.axial_offset_m.
void place_on_tool(const RigidTool& tool, const double* reference, double* x, std::size_t n);

}  // namespace sphforge
