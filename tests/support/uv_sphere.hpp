// A UV sphere as a triangle mesh (poles at +-r on z, nt latitude bands, np longitudes, triangles
// wound outwards), for the STL-mesh tool tests and benchmarks: a closed mesh large enough for the
// bounding-volume hierarchy to matter, whose exact surface is known.
#pragma once

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Core>

namespace sphforge_test {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
};

inline TriangleMesh uv_sphere(double r, int nt, int np) {
  TriangleMesh m;
  m.points.emplace_back(0, 0, r);
  for (int i = 1; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const double th = std::numbers::pi * i / nt, ph = 2 * std::numbers::pi * j / np;
      m.points.emplace_back(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th));
    }
  m.points.emplace_back(0, 0, -r);
  const int south = static_cast<int>(m.points.size()) - 1;
  auto id = [&](int i, int j) { return 1 + (i - 1) * np + (j % np); };
  for (int j = 0; j < np; ++j) {
    m.triangles.push_back({0, id(1, j), id(1, j + 1)});
    m.triangles.push_back({south, id(nt - 1, j + 1), id(nt - 1, j)});
  }
  for (int i = 1; i + 1 < nt; ++i)
    for (int j = 0; j < np; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

}  // namespace sphforge_test
