// The friction_extrusion process end to end (docs/processes/friction_extrusion.md): its user errors
// are input errors (exit code 2, file and JSON pointer), its friction heat rate (docs/theory.md
// eq. 104) is the core's per-tool friction heat (eq. 18e) divided by the time scaling, and its scene
// stands where eqs. 92 and 99a put it. The steady-state checks of the bundled quick case are
// the CTest case.friction_extrusion.aa7075_pid_300kN_quick (tests/cases/fe_quick.cmake).
#include <gtest/gtest.h>

#include "process_runs.hpp"

#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using namespace sphforge_test;

namespace {

const std::string kQuick = std::string(SPHFORGE_SOURCE_DIR) + "/cases/friction_extrusion/aa7075_pid_300kN_quick.json";
const std::string kFsbeQuick = std::string(SPHFORGE_SOURCE_DIR) + "/cases/fsbe/brass_wire_quick.json";

Result sphforge(const std::vector<std::string>& args, const fs::path& dir) { return run_sphforge(args, dir); }

fs::path scratch(const std::string& name) { return scratch_folder("fe", name); }

/// The FSBE quick case's scene as built (frame 0 of a run stopped after its first step) at 3 mm
/// spacing (the geometry the scene tests count on, whatever the case's own spacing), with
/// `overrides` ("key=value" for --set), in the scratch folder `name`.
vtkSmartPointer<vtkUnstructuredGrid> built_fsbe_scene(const std::string& name, const std::vector<std::string>& overrides) {
  const fs::path dir = scratch(name);
  std::vector<std::string> args = {"run",   kFsbeQuick, "--out", "out", "--quiet", "--set", "run.end_time=1e-7 s",
                                   "--set", "process.particle_spacing=3 mm"};
  for (const std::string& o : overrides) args.insert(args.end(), {"--set", o});
  const Result r = sphforge(args, dir);
  EXPECT_EQ(r.code, 0) << describe(r);
  return r.code == 0 ? read_particle_frame(dir / "out" / "particles_000000.vtu") : nullptr;
}

/// The body index of a particle at which `where(x)` holds (-1 when none does).
template <class Where>
double body_of_a_particle(vtkUnstructuredGrid* grid, Where where) {
  vtkDataArray* body = grid->GetPointData()->GetArray("body");
  for (vtkIdType i = 0; body != nullptr && i < grid->GetNumberOfPoints(); ++i) {
    double x[3];
    grid->GetPoint(i, x);
    if (where(x)) return body->GetTuple1(i);
  }
  return -1.0;
}

/// history.csv of a finished run: the header's names and the rows' numbers.
struct Table {
  std::vector<std::string> head;
  std::vector<std::vector<double>> rows;
  std::size_t column(const std::string& name) const {
    for (std::size_t k = 0; k < head.size(); ++k)
      if (head[k] == name) return k;
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
};
/// Only complete rows are kept (a row with fewer cells than the header is a partial last line).
Table read_table(const fs::path& file) {
  Table t;
  const std::vector<std::string> lines = lines_of(slurp(file));
  if (lines.empty()) return t;
  t.head = split(lines[0], ',');
  for (std::size_t r = 1; r < lines.size(); ++r) {
    std::vector<double> row;
    for (const std::string& cell : split(lines[r], ',')) row.push_back(std::strtod(cell.c_str(), nullptr));
    if (row.size() == t.head.size()) t.rows.push_back(row);
  }
  return t;
}

TEST(FrictionExtrusion, QuarterSectorWithThermalToolBodiesFollowsTheFullRun) {
  // The quick case (die and container as attached thermal bodies, theory eq. 32a) whole and as a
  // 90 deg sector (sector_count 4: the process multiplies the die's reaction by 4, eq. 101), 0.03 s.
  // The two agree to round-off (1e-13) for the first ~60 steps; then a threshold event (a particle
  // entering a contact or switching between sticking and sliding one step apart, set off by the
  // other summation order) moves the PID loop's force by ~1e-3. The same happens without thermal
  // bodies (measured: force 1.1e-3, with them 1.9e-3; die thermocouple 4e-4). Bounds: 1e-2 on the
  // force, 2e-3 on the temperatures, 5 x the measured spread; a sector carrying 1/4 of the force
  // without the factor, or heat lost at the cuts, would be off by 75 % or by kelvins.
  const fs::path full = scratch("full"), sector = scratch("sector");
  const std::vector<std::string> common = {"run", kQuick, "--out", "out", "--quiet", "--set", "run.end_time=0.03 s",
                                           "--set", "run.history_interval=1 ms"};
  std::vector<std::string> quarter = common;
  for (const char* a : {"--set", "process.sector_count=4", "--set", R"(numerics.symmetry={"sector":{"angle":"90 deg"}})"})
    quarter.push_back(a);
  const Result rf = sphforge(common, full), rs = sphforge(quarter, sector);
  ASSERT_EQ(rf.code, 0) << describe(rf);
  ASSERT_EQ(rs.code, 0) << describe(rs);
  const Table a = read_table(full / "out" / "history.csv"), b = read_table(sector / "out" / "history.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_GT(a.rows.size(), 20u);
  double force = 0.0, temperature = 0.0;
  for (std::size_t r = 1; r < a.rows.size(); ++r) {
    const std::size_t f = a.column("extrusion_force_N");
    force = std::max(force, std::abs(a.rows[r][f] - b.rows[r][f]) / std::abs(a.rows[r][f]));
    for (const char* name : {"die_thermocouple_K", "billet_tc_r6p25mm_d5mm_K"}) {
      const std::size_t c = a.column(name);
      temperature = std::max(temperature, std::abs(a.rows[r][c] - b.rows[r][c]) / a.rows[r][c]);
    }
  }
  std::printf("sector against full run: force max rel %.3g, temperatures max rel %.3g\n", force, temperature);
  EXPECT_LT(force, 1e-2);
  EXPECT_LT(temperature, 2e-3);
}

TEST(FrictionExtrusion, MissingPlasticRateOutputIsAnInputError) {
  // Z (eq. 106) and the plastic heat rate (eq. 105) need the material's plastic_strain_rate output.
  const Result r = sphforge({"run", kQuick, "--out", "out", "--set", "material.output_fields=[]"}, scratch("rate"));
  EXPECT_EQ(r.code, 2) << describe(r);
  EXPECT_TRUE(contains(r.err, "at /material/output_fields")) << r.err;
}

TEST(FrictionExtrusion, FrictionHeatRateIsTheCoresFrictionHeatOverTheTimeScaling) {
  const fs::path dir = scratch("heat");
  const Result r = sphforge({"run", kQuick, "--out", "out", "--quiet", "--set", "run.end_time=0.03 s", "--set",
                             "run.history_interval=1 ms"},
                            dir);
  ASSERT_EQ(r.code, 0) << describe(r);
  const Table t = read_table(dir / "out" / "history.csv");
  ASSERT_GT(t.rows.size(), 10u);
  const std::size_t process = t.column("friction_heat_rate_W"), core = t.column("die_friction_heat_W");
  int compared = 0;
  double worst = 0.0;
  for (const std::vector<double>& v : t.rows) {
    const double q_process = v[process], q_core = v[core];
    if (q_core <= 0.0) continue;
    worst = std::max(worst, std::abs(10.0 * q_process - q_core) / q_core);  // time_scaling 10 (eq. 104)
    ++compared;
  }
  EXPECT_GT(compared, 10);
  // Both are the contact pass's sum for the die; the process column is that sum x N / f (the quick
  // case is a whole 360 deg run, N = 1). So they agree to the round-off of the scaling and of
  // printing 17 digits; a wrong scaling (x f or / f) or a sum that misses contacts (the recomputation
  // before 2026-12-06 missed the corner ring, 41 % here) is off by far more.
  EXPECT_LT(worst, 1e-12) << compared << " rows";
}

TEST(FrictionExtrusion, TimeMeanForceIsTheStepWeightedHistoryMean) {
  // Eq. 108a: the summary's time mean of the force over the steady window equals the history's
  // per-step forces weighted by their process-time steps, the history written at every step
  // (history_interval far below the step). Both sum the same doubles in a different order (running
  // sums against this loop over the printed rows, 17 digits): 1e-9 bounds that. Also checked: the
  // sample mean of eq. 108 differs from the time mean by more than that (the aliasing eq. 108a is there
  // for), so the comparison would notice a time mean that fell back to the samples. The contact runs at
  // the default stiffness factor 1, where the sampled loop cycles (theory eq. 109a): the force settles
  // within 0.2 s of process and then saw-tooths, the input eq. 108a is for (at the case's 0.05 it
  // settles only after 0.7 s, past this short run).
  const fs::path dir = scratch("timemean");
  const Result r = sphforge({"run", kQuick, "--out", "out", "--quiet", "--set", "run.end_time=0.05 s", "--set",
                             "run.history_interval=1e-9 s", "--set", "contact.stiffness_factor=1"},
                            dir);
  ASSERT_EQ(r.code, 0) << describe(r);
  std::ifstream in(dir / "out" / "summary.json");
  const nlohmann::json metrics = nlohmann::json::parse(in).at("metrics");
  ASSERT_TRUE(metrics.contains("steady_time_mean_force_N")) << metrics.dump(1);
  const double t_a = metrics.at("steady_start_time_s").get<double>();
  const double time_mean = metrics.at("steady_time_mean_force_N").get<double>();
  const double sample_mean = metrics.at("steady_mean_force_N").get<double>();
  const Table t = read_table(dir / "out" / "history.csv");
  const std::size_t time = t.column("process_time_s"), force = t.column("extrusion_force_N");
  double integral = 0.0, t_end = t_a, previous = 0.0;
  int steps = 0;
  for (const std::vector<double>& v : t.rows) {
    if (v[time] > t_a) integral += v[force] * (v[time] - previous), t_end = v[time], ++steps;
    previous = v[time];
  }
  ASSERT_GT(steps, 100);
  const double history_mean = integral / (t_end - t_a);
  std::printf("steady window from %.4f to %.4f s of process, %d steps: time mean %.6f kN (history %.6f kN), "
              "sample mean %.6f kN\n",
              t_a, t_end, steps, time_mean / 1e3, history_mean / 1e3, sample_mean / 1e3);
  EXPECT_NEAR(time_mean, history_mean, 1e-9 * std::abs(history_mean));
  EXPECT_GT(std::abs(sample_mean - history_mean), 1e-9 * std::abs(history_mean));
}

TEST(FrictionExtrusion, DieBodyFollowsAConicalFaceHalfASpacingBehindIt) {
  // Eq. 92 makes the contact a perfect thermal interface only if the tool's thermal particles sit
  // dx/2 behind its surface, as the workpiece's sit dx/2 in front. The FSBE quick case's face rises
  // by 2 mm from the container wall (r = 15 mm) to the bore (r = 3.5 mm) at dx = 3 mm, its die body
  // is 6 mm thick (2 layers), and the billet's top, hence the flat face level z0, is at 13 dx = 39 mm.
  // Every column of the die body must hold layers at face(r) + (k + 1/2) dx, k = 0, 1: the first
  // one included. (A fixed-z lattice cut by the cone lost the first layer wherever the face rises,
  // leaving the nearest die particles up to 3 dx/2 behind it; measured on 2026-12-06 at 2 mm, the tool
  // thermocouple of the full case then read 345 K instead of 545 K after its first second.) The frame at t = 0 is
  // the built scene; 1e-9 m is round-off on millimetre coordinates.
  const vtkSmartPointer<vtkUnstructuredGrid> grid = built_fsbe_scene("conical_die_body", {});
  ASSERT_NE(grid, nullptr);
  vtkDataArray* body = grid->GetPointData()->GetArray("body");
  ASSERT_NE(body, nullptr);
  const double dx = 3e-3, z0 = 39e-3, radius = 15e-3, orifice = 3.5e-3, rise = 2e-3;
  const auto face = [&](double rr) { return z0 + rise * std::clamp((radius - rr) / (radius - orifice), 0.0, 1.0); };
  // The die body: the only body with particles above the flat face level inside the container.
  const double die_id =
      body_of_a_particle(grid, [&](const double* x) { return x[2] > z0 + 1e-9 && std::hypot(x[0], x[1]) < radius; });
  ASSERT_GE(die_id, 0.0);
  std::map<std::pair<long, long>, std::vector<int>> layers;  // column (x, y in um) -> layer indices
  int particles = 0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    if (body->GetTuple1(i) != die_id) continue;
    double x[3];
    grid->GetPoint(i, x);
    const double height = (x[2] - face(std::hypot(x[0], x[1]))) / dx - 0.5;  // k
    EXPECT_NEAR(height, std::round(height), 1e-9 / dx) << "die particle at (" << x[0] << ", " << x[1] << ", " << x[2] << ")";
    layers[{std::lround(x[0] * 1e6), std::lround(x[1] * 1e6)}].push_back(static_cast<int>(std::lround(height)));
    ++particles;
  }
  ASSERT_GT(layers.size(), 5u);
  for (auto& [column, k] : layers) {
    std::sort(k.begin(), k.end());
    EXPECT_EQ(k, (std::vector<int>{0, 1})) << "column at (" << column.first << ", " << column.second << ") um";
  }
  std::printf("die body: %d particles in %zu columns\n", particles, layers.size());
}

TEST(FrictionExtrusion, ContainerWallBodyStandsInRingsHalfASpacingOutsideTheBore) {
  // The same requirement as the die body's (eq. 92) at the container's cylindrical wall r = R: its
  // thermal particles must sit on rings at R + (l + 1/2) dx. The FSBE quick case: R = 15 mm,
  // dx = 3 mm, here with a 6 mm wall (2 rings; the case's 3 mm makes one), a 90 deg sector (numerics.symmetry): each ring
  // layer holds round(2 pi r / (4 dx)) sites of the sector, a pitch of 2 pi r / sites apart and half a
  // pitch off the cut planes, so the sector's images make whole rings (eq. 30). (The cubic lattice
  // cut at r >= R + dx/2, before 2026-12-06, put the first wall particles a median 1.07 dx from the
  // wall at 2 mm in the AA7075 case.) 1e-9 m is round-off on millimetre coordinates.
  const vtkSmartPointer<vtkUnstructuredGrid> grid =
      built_fsbe_scene("container_rings", {"process.container_wall_thickness=6 mm"});
  ASSERT_NE(grid, nullptr);
  vtkDataArray* body = grid->GetPointData()->GetArray("body");
  ASSERT_NE(body, nullptr);
  const double dx = 3e-3, radius = 15e-3, pi = 3.14159265358979323846;
  // The container body: the only body with particles outside the bore above the bottom (z > 0).
  const double container_id =
      body_of_a_particle(grid, [&](const double* x) { return x[2] > 0.0 && std::hypot(x[0], x[1]) > radius; });
  ASSERT_GE(container_id, 0.0);
  std::map<std::pair<int, long>, std::vector<double>> rings;  // (ring l, height in um) -> polar angles
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    if (body->GetTuple1(i) != container_id) continue;
    double x[3];
    grid->GetPoint(i, x);
    if (x[2] < 0.0) continue;  // the bottom: a lattice under a flat wall
    const double ring = (std::hypot(x[0], x[1]) - radius) / dx - 0.5;  // l
    EXPECT_NEAR(ring, std::round(ring), 1e-9 / dx) << "wall particle at (" << x[0] << ", " << x[1] << ", " << x[2] << ")";
    rings[{static_cast<int>(std::lround(ring)), std::lround(x[2] * 1e6)}].push_back(std::atan2(x[1], x[0]));
  }
  std::set<int> ring_numbers;
  for (auto& [key, angles] : rings) {
    ring_numbers.insert(key.first);
    const double r_ring = radius + (key.first + 0.5) * dx;
    const long sites = 4 * std::max(1L, std::lround(2.0 * pi * r_ring / (4.0 * dx)));
    ASSERT_EQ(static_cast<long>(angles.size()), sites / 4) << "ring " << key.first << " at z = " << key.second << " um";
    std::sort(angles.begin(), angles.end());
    const double pitch = 2.0 * pi / static_cast<double>(sites);
    for (std::size_t m = 0; m < angles.size(); ++m)
      EXPECT_NEAR(angles[m], (m + 0.5) * pitch, 1e-9) << "ring " << key.first << " at z = " << key.second << " um";
  }
  EXPECT_EQ(ring_numbers, (std::set<int>{0, 1}));
  std::printf("container wall: %zu ring layers, rings at R + dx/2 and R + 3 dx/2\n", rings.size());
}

TEST(FrictionExtrusion, BilletSideStandsHalfASpacingInsideTheContainerWall) {
  // The billet must fill the bore: its side touches the wall at r = R as its bottom touches z = 0,
  // that is its outermost particles stand dx/2 inside (the contact's reach, eq. 11), on one ring per
  // layer at R - dx/2 with round(2 pi r / (4 dx)) sites in the 90 deg sector, half a pitch off the cut
  // planes (eq. 30), and the cubic lattice inside r <= R - dx. FSBE quick case: R = 15 mm, dx = 3 mm.
  // (The lattice cut at R - dx/2 alone, before 2026-12-06, left its outermost particles a median
  // 1.02 dx inside the wall at 2 mm, out of the contact's reach, and held 76 % of this billet's volume.)
  // Volume: each layer's count x dx^3 within 3 % of the quarter disc pi R^2 / 4 x dx; the lattice's
  // ragged cut at five spacings across the radius makes +1.9 %. 1e-9 m is round-off on millimetres.
  const vtkSmartPointer<vtkUnstructuredGrid> grid = built_fsbe_scene("billet_rim", {});
  ASSERT_NE(grid, nullptr);
  vtkDataArray* body = grid->GetPointData()->GetArray("body");
  ASSERT_NE(body, nullptr);
  const double dx = 3e-3, radius = 15e-3, z_face = 39e-3, pi = 3.14159265358979323846;
  const double billet_id = body_of_a_particle(grid, [&](const double* x) {
    return x[2] > 0.0 && x[2] < z_face && std::hypot(x[0], x[1]) < radius - 1e-9;
  });
  ASSERT_GE(billet_id, 0.0);
  std::map<long, int> per_layer;            // height in um -> particles
  std::map<long, std::vector<double>> rim;  // height in um -> polar angles on the rim ring
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    if (body->GetTuple1(i) != billet_id) continue;
    double x[3];
    grid->GetPoint(i, x);
    const long layer = std::lround(x[2] * 1e6);
    ++per_layer[layer];
    const double r = std::hypot(x[0], x[1]);
    if (r <= radius - dx + 1e-9) continue;  // the lattice inside
    EXPECT_NEAR(r, radius - 0.5 * dx, 1e-9) << "billet particle at (" << x[0] << ", " << x[1] << ", " << x[2] << ")";
    rim[layer].push_back(std::atan2(x[1], x[0]));
  }
  ASSERT_EQ(per_layer.size(), 13u);
  ASSERT_EQ(rim.size(), per_layer.size()) << "every layer has its rim ring";
  const long sites = 4 * std::max(1L, std::lround(2.0 * pi * (radius - 0.5 * dx) / (4.0 * dx)));
  for (auto& [layer, angles] : rim) {
    ASSERT_EQ(static_cast<long>(angles.size()), sites / 4) << "rim ring at z = " << layer << " um";
    std::sort(angles.begin(), angles.end());
    for (std::size_t m = 0; m < angles.size(); ++m)
      EXPECT_NEAR(angles[m], (m + 0.5) * 2.0 * pi / static_cast<double>(sites), 1e-9) << "z = " << layer << " um";
  }
  const double quarter_disc = 0.25 * pi * radius * radius * dx;
  for (const auto& [layer, count] : per_layer)
    EXPECT_NEAR(count * dx * dx * dx / quarter_disc, 1.0, 0.03) << "layer at z = " << layer << " um";
  std::printf("billet: %d particles per layer (quarter disc %.2f dx^2), %ld on the rim ring at R - dx/2\n",
              per_layer.begin()->second, quarter_disc / (dx * dx * dx), sites / 4);
}

}  // namespace
