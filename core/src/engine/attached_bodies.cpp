#include "engine/attached_bodies.hpp"

#include <cmath>

namespace sphforge {

void attach_to_tool(const RigidTool& tool, const double* x, double* reference, std::size_t n) {
  // Inverse of eq. 90: rotate by -theta about z after removing the axial offset.
  const double c = std::cos(tool.angle_rad), s = std::sin(tool.angle_rad), w = tool.axial_offset_m;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double px = x[3 * i], py = x[3 * i + 1];
    reference[3 * i] = c * px + s * py;
    reference[3 * i + 1] = -s * px + c * py;
    reference[3 * i + 2] = x[3 * i + 2] - w;
  }
}

void place_on_tool(const RigidTool& tool, const double* reference, double* x, std::size_t n) {
  // Eq. 90, from the reference positions every step: the pose (theta, w) is the tool's own
  // integrated state, so the particles sit exactly where the tool surface is, without the
  // drift an incremental update x += v dt would pile up on a rotating tool.
  const double c = std::cos(tool.angle_rad), s = std::sin(tool.angle_rad), w = tool.axial_offset_m;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double X = reference[3 * i], Y = reference[3 * i + 1];
    x[3 * i] = c * X - s * Y;
    x[3 * i + 1] = s * X + c * Y;
    x[3 * i + 2] = reference[3 * i + 2] + w;
  }
}

}  // namespace sphforge
