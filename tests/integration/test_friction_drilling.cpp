// The friction_drilling process's scene (docs/processes/friction_drilling.md): the drill's thermal
// body is built for the perfect thermal contact of docs/theory.md eq. 92 (eq. 122). The bundled
// quick case's runs are the CTests case.friction_drilling.hx220_m4_quick and
// integration.friction_drilling.* (tests/cases/friction_drilling_*.cmake).
#include <gtest/gtest.h>

#include "process_runs.hpp"

#include <vtkDataArray.h>
#include <vtkPointData.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace sphforge_test;

namespace {

/// Distance from (r, z) to the polyline through `points` (r, z in m).
double distance_to_profile(const std::vector<std::array<double, 2>>& points, double r, double z) {
  double best = 1e300;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const double ar = points[k][0], az = points[k][1], dr = points[k + 1][0] - ar, dz = points[k + 1][1] - az;
    const double t = std::clamp(((r - ar) * dr + (z - az) * dz) / (dr * dr + dz * dz), 0.0, 1.0);
    best = std::min(best, std::hypot(r - ar - t * dr, z - az - t * dz));
  }
  return best;
}

TEST(FrictionDrilling, DrillBodyLayersSitAtHalfSpacingsBehindTheProfile) {
  // Eq. 122: every drill-body particle lies (n + 1/2) dx behind the drill's surface, so the outer
  // layer is dx/2 behind it (eq. 92's perfect contact), and the body holds the drill's volume.
  // The quick case at 0.4 mm, whole (no sector), the drill body 6 mm long, with the default profile
  // written out (r, z in m, tip at z = 0): tip cone to (0.6, 0.35) mm, forming cone to (1.85, 3.85)
  // mm, cylinder. The profile is convex, so each particle's nearest segment is the one it was moved
  // along: the depths are exact to round-off (1e-9 dx). Volume of the first 6 mm: tip cone, frustum,
  // cylinder; the slabs' sites fill it to their lattice's resolution (measured +0.09 %; 0.5 %
  // allowed). The cubic lattice cut at dx/2 before 2026-12-06 failed both: depths anywhere from
  // dx/2 to 3 dx/2 and a quarter of the volume missing (480 particles, 30.7 mm^3).
  const std::vector<std::array<double, 2>> profile = {{0, 9e-3}, {1.85e-3, 9e-3}, {1.85e-3, 3.85e-3}, {0.6e-3, 0.35e-3}, {0, 0}};
  const fs::path dir = scratch_folder("fd", "drill_body");
  const Result r = run_sphforge({"run", std::string(SPHFORGE_SOURCE_DIR) + "/cases/friction_drilling/hx220_m4_quick.json",
                                 "--out", "out", "--quiet", "--set", "run.end_time=1e-9 s", "--set",
                                 "process.drill_profile=[[0,0.009],[0.00185,0.009],[0.00185,0.00385],[0.0006,0.00035],[0,0]]",
                                 "--set", "process.drill_body_length=6 mm", "--set", "process.particle_spacing=0.4 mm"},
                                dir);
  ASSERT_EQ(r.code, 0) << describe(r);
  const vtkSmartPointer<vtkUnstructuredGrid> grid = read_particle_frame(dir / "out" / "particles_000000.vtu");
  vtkDataArray* body = grid->GetPointData()->GetArray("body");
  vtkDataArray* reference = grid->GetPointData()->GetArray("tool_reference_position");  // drill frame (eq. 90)
  ASSERT_NE(body, nullptr);
  ASSERT_NE(reference, nullptr);
  const double dx = 0.4e-3;
  int particles = 0, outer = 0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    if (body->GetTuple1(i) != 1.0) continue;  // body 0 the sheet, 1 the drill body
    const double* X = reference->GetTuple3(i);
    const double rr = std::hypot(X[0], X[1]), z = X[2];
    const double layer = distance_to_profile(profile, rr, z) / dx - 0.5;
    EXPECT_NEAR(layer, std::round(layer), 1e-9) << "drill particle at r = " << rr << ", z = " << z;
    EXPECT_GE(layer, -1e-9);
    outer += std::lround(layer) == 0;
    ++particles;
  }
  const double pi = std::numbers::pi;
  const double volume = pi / 3 * 0.6e-3 * 0.6e-3 * 0.35e-3 +
                        pi / 3 * 3.5e-3 * (0.6e-3 * 0.6e-3 + 0.6e-3 * 1.85e-3 + 1.85e-3 * 1.85e-3) +
                        pi * 1.85e-3 * 1.85e-3 * (6e-3 - 3.85e-3);
  std::printf("drill body: %d particles (%d in the outer layer), volume %.4f mm^3 against %.4f mm^3\n", particles, outer,
              particles * dx * dx * dx * 1e9, volume * 1e9);
  EXPECT_NEAR(particles * dx * dx * dx, volume, 5e-3 * volume);
  EXPECT_GT(outer, 0);
}

}  // namespace

namespace {
struct SheetCells {
  double volume = 0.0;  // sum of m / rho over the sheet
  int fine = 0, coarse = 0, drill = 0;
  double fine_r_max = 0.0, coarse_r_min = 1e300, drill_h_min = 1e300, drill_h_max = 0.0;
};

SheetCells read_sheet(const fs::path& frame, double fine_h) {
  const vtkSmartPointer<vtkUnstructuredGrid> grid = read_particle_frame(frame);
  vtkDataArray* body = grid->GetPointData()->GetArray("body");
  vtkDataArray* mass = grid->GetPointData()->GetArray("mass");
  vtkDataArray* density = grid->GetPointData()->GetArray("density");
  vtkDataArray* h = grid->GetPointData()->GetArray("smoothing_length");  // only with several spacings
  SheetCells s;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    const double* x = grid->GetPoint(i);
    const double hi = h ? h->GetTuple1(i) : 0.0;
    if (body->GetTuple1(i) != 0.0) {
      ++s.drill;
      s.drill_h_min = std::min(s.drill_h_min, hi), s.drill_h_max = std::max(s.drill_h_max, hi);
      continue;
    }
    s.volume += mass->GetTuple1(i) / density->GetTuple1(i);
    const double r = std::hypot(x[0], x[1]);
    if (h && std::abs(hi - fine_h) < 1e-12) {
      ++s.fine;
      s.fine_r_max = std::max(s.fine_r_max, r);
    } else {
      ++s.coarse;
      s.coarse_r_min = std::min(s.coarse_r_min, r);
    }
  }
  return s;
}
}  // namespace

TEST(FrictionDrilling, RefinedCentreSplitsTheCoarseCellsWithoutChangingTheSheet) {
  // Eq. 121c: with refined_diameter 5 mm and refined_spacing 0.2 mm (the paper's discretisation) every
  // 0.4 mm cell whose centre lies within 2.5 mm of the axis becomes 8 cells of 0.2 mm. The sheet keeps
  // the coarse lattice's volume (to round-off: the fine cells tile the coarse ones exactly), the fine
  // particles lie within 2.5 mm + a coarse cell's half-diagonal in plan, the coarse ones outside
  // 2.5 mm minus it, each particle has h = 1.3 s (field smoothing_length), and the drill body takes
  // the fine spacing. A sector with a refined centre is refused (exit 2, naming the parameter).
  const std::string quick = std::string(SPHFORGE_SOURCE_DIR) + "/cases/friction_drilling/hx220_m4_quick.json";
  const fs::path dir = scratch_folder("fd", "refined");
  const Result coarse = run_sphforge({"run", quick, "--out", "coarse", "--quiet", "--set", "run.end_time=1e-9 s"}, dir);
  ASSERT_EQ(coarse.code, 0) << describe(coarse);
  const Result refined = run_sphforge({"run", quick, "--out", "refined", "--quiet", "--set", "run.end_time=1e-9 s", "--set",
                                       "process.refined_diameter=5 mm", "--set", "process.refined_spacing=0.2 mm"},
                                      dir);
  ASSERT_EQ(refined.code, 0) << describe(refined);
  const SheetCells c = read_sheet(dir / "coarse" / "particles_000000.vtu", 0.0);
  const SheetCells f = read_sheet(dir / "refined" / "particles_000000.vtu", 1.3 * 0.2e-3);
  EXPECT_NEAR(f.volume, c.volume, 1e-12 * c.volume);
  ASSERT_GT(f.fine, 0);
  EXPECT_EQ(f.fine % 8, 0);
  EXPECT_EQ(f.fine / 8 + f.coarse, c.coarse);  // every coarse cell either kept or split in 8
  const double half_diagonal = std::sqrt(0.5) * 0.4e-3;
  EXPECT_LT(f.fine_r_max, 2.5e-3 + half_diagonal);
  EXPECT_GT(f.coarse_r_min, 2.5e-3 - half_diagonal);
  EXPECT_NEAR(f.drill_h_min, 1.3 * 0.2e-3, 1e-15);
  EXPECT_NEAR(f.drill_h_max, 1.3 * 0.2e-3, 1e-15);
  std::printf("refined centre: %d fine + %d coarse sheet particles (coarse lattice %d), drill body %d, sheet volume "
              "%.6f mm^3 (coarse %.6f)\n",
              f.fine, f.coarse, c.coarse, f.drill, f.volume * 1e9, c.volume * 1e9);

  const Result sector = run_sphforge({"run", std::string(SPHFORGE_SOURCE_DIR) + "/cases/friction_drilling/hx220_m4.json",
                                      "--out", "sector", "--quiet", "--set", "run.end_time=1e-9 s", "--set",
                                      "process.refined_diameter=5 mm", "--set", "process.refined_spacing=0.1 mm"},
                                     dir);
  EXPECT_EQ(sector.code, 2) << describe(sector);
  EXPECT_NE(sector.err.find("refined_diameter"), std::string::npos) << describe(sector);
}
