// Cost of one signed-distance query per tool shape (docs/theory.md section 3.1), through the
// batch call the contact pass uses (RigidTool::signed_distance(count, x, d, normal), no culling).
// Points: 4096 per batch, in a turned and lifted pose (so the body-frame transform is included),
// either uniformly random in a 50 mm box around the tool (BM_ToolQuery) or within 0.5 mm of its
// surface like the candidates the contact pass keeps (BM_ToolQueryNearSurface). items_per_second = queries per second on the threads
// OpenMP gives it; run `OMP_NUM_THREADS=1 sphforge_bench_tools` for the cost per query per core.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "sphforge/tool.hpp"
#include "tools/shapes.hpp"
#include "uv_sphere.hpp"

namespace {

using namespace sphforge;
using Vec = Eigen::Vector3d;

/// A UV sphere of radius r with nt x np facets pairs (a mesh large enough for the hierarchy to matter).
RigidTool sphere_mesh(double r, int nt, int np) {
  const sphforge_test::TriangleMesh m = sphforge_test::uv_sphere(r, nt, np);
  return RigidTool("sphere", make_mesh_shape(m.points, m.triangles));
}

RigidTool make(int kind) {
  switch (kind) {
    case 0: return RigidTool::plane("plane", Vec(0, 0, 0), Vec(0.2, 0.1, 1.0), 0.05);
    case 1: return RigidTool::cylinder("barrel", 0.02, -0.05, 0.05, true);
    case 2:  // the paste die: underside, land, filleted entry, face (ram_extrusion)
      return RigidTool("die", ToolProfile({{0.02, -0.002}, {0.005, -0.002}, {0.005, 0.0}, {0.02, 0.0}}).with_fillets(3e-4, {2}));
    case 3: return RigidTool::stl("box", std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/tools/box_10mm.stl", 1e-3);
    default: return sphere_mesh(0.02, 100, 200);  // 39 600 triangles
  }
}

void BM_ToolQuery(benchmark::State& state) {
  RigidTool tool = make(static_cast<int>(state.range(0)));
  tool.axial_offset_m = 1e-3;
  tool.angle_rad = 0.3;
  const std::size_t n = 4096;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.025, 0.025);
  std::vector<double> x(3 * n), d(n), normal(3 * n);
  for (double& c : x) c = u(rng);
  for (auto _ : state) {
    tool.signed_distance(n, x.data(), d.data(), normal.data());
    benchmark::DoNotOptimize(d.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n));
  state.SetLabel(tool.shape().kind());
}
BENCHMARK(BM_ToolQuery)->ArgName("shape")->DenseRange(0, 4);

/// range(1) = 1: the points ordered along the surface (as Z-ordered particles reach the contact
/// pass), 0: in random order.
void BM_ToolQueryNearSurface(benchmark::State& state) {
  RigidTool tool = make(static_cast<int>(state.range(0)));
  tool.axial_offset_m = 1e-3;
  tool.angle_rad = 0.3;
  const SurfaceMesh surface = tool.surface(48);
  const std::size_t n = 4096;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-5e-4, 5e-4);
  std::uniform_int_distribution<std::size_t> pick(0, surface.points.size() - 1);
  std::vector<double> x(3 * n), d(n), normal(3 * n);
  std::vector<std::size_t> at(n);
  for (auto& a : at) a = pick(rng);
  if (state.range(1) == 1) std::sort(at.begin(), at.end());
  for (std::size_t i = 0; i < n; ++i) {
    const Vec p = surface.points[at[i]];
    for (int c = 0; c < 3; ++c) x[3 * i + c] = p[c] + u(rng);
  }
  for (auto _ : state) {
    tool.signed_distance(n, x.data(), d.data(), normal.data());
    benchmark::DoNotOptimize(d.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n));
  state.SetLabel(tool.shape().kind());
}
BENCHMARK(BM_ToolQueryNearSurface)->ArgNames({"shape", "ordered"})->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}});

}  // namespace
