// The sphforge command end to end: the output contract of a run (read back with VTK), exit codes
// and messages of invalid input and of a numerical blow-up, check, plugins, --out/--force, and
// that the executable does not link any plugin.
#include <gtest/gtest.h>

#include "command_line.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

namespace fs = std::filesystem;
using nlohmann::json;
using namespace sphforge_test;

namespace {

const std::string kExe = SPHFORGE_EXECUTABLE;
const std::string kCoreLibrary = SPHFORGE_CORE_LIBRARY;
const std::string kQuickCase = std::string(SPHFORGE_SOURCE_DIR) + "/cases/ram_extrusion/paste_orifice_quick.json";

// A tiny case (4 layers of 1 mm, 1792 particles) for runs that only need to start.
// Pins geometry and density so that the tests do not depend on how the bundled case is tuned.
const std::vector<std::string> kTinyCase = {"--set", "process.billet_height=4 mm", "--set",
                                            "process.particle_spacing=1 mm", "--set",
                                            "material.density=1e7 kg/m^3"};

/// Runs a shell command line in `cwd`, capturing stdout and stderr separately (into files in
/// `capture_dir`, never in `cwd`) and the exit status. SPHFORGE_PLUGIN_PATH is removed from the
/// environment so that only the build's own plugin folder is searched. OMP_WAIT_POLICY=PASSIVE:
/// on a busy machine (ctest -j, a small CI runner) spinning OpenMP barriers make a run several
/// times slower (52 s instead of 17 s for the 300-step run below); results do not depend on it.
Result run_shell(const std::string& command, const fs::path& cwd, const fs::path& capture_dir) {
  static int counter = 0;
  const fs::path out = capture_dir / ("stdout_" + std::to_string(counter) + ".txt");
  const fs::path err = capture_dir / ("stderr_" + std::to_string(counter) + ".txt");
  ++counter;
  const std::string line = "cd " + shell_quote(cwd.string()) + " && env -u SPHFORGE_PLUGIN_PATH OMP_WAIT_POLICY=PASSIVE " + command + " >" +
                           shell_quote(out.string()) + " 2>" + shell_quote(err.string());
  const int status = std::system(line.c_str());
  Result r;
  if (status == -1) r.code = -1;
  else if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  else if (WIFSIGNALED(status)) r.code = 128 + WTERMSIG(status);
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

/// Runs sphforge with `args` (a hard time limit guards against a run that never ends).
Result sphforge(const std::vector<std::string>& args, const fs::path& cwd, const fs::path& capture_dir) {
  std::string cmd = "timeout -k 10 300 " + shell_quote(kExe);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  return run_shell(cmd, cwd, capture_dir);
}

/// A fresh folder per test: `work` is the current directory of the commands, `capture` holds
/// their captured output, and the test's own files go to root(). Kept when the test fails.
class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / ("sphforge_cli_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "work");
    fs::create_directories(root_ / "capture");
  }
  void TearDown() override {
    std::error_code ec;
    if (!HasFailure()) fs::remove_all(root_, ec);
    else std::fprintf(stderr, "files of the failed test kept in %s\n", root_.c_str());
  }
  Result run(const std::vector<std::string>& args) { return sphforge(args, work(), root_ / "capture"); }
  fs::path work() const { return root_ / "work"; }
  fs::path root() const { return root_; }

  fs::path root_;
};

json read_json(const fs::path& file) {
  std::ifstream in(file);
  return json::parse(in);
}

struct PvdEntry {
  double time;
  int part;
  std::string file;
};

/// Parses a .pvd collection with VTK's XML parser.
std::vector<PvdEntry> read_pvd(const fs::path& file) {
  std::vector<PvdEntry> out;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(file.string().c_str());
  if (parser->Parse() != 1) {
    ADD_FAILURE() << "cannot parse " << file;
    return out;
  }
  vtkXMLDataElement* root = parser->GetRootElement();
  if (!root || std::string(root->GetName()) != "VTKFile" || !root->GetAttribute("type") ||
      std::string(root->GetAttribute("type")) != "Collection" || root->GetNumberOfNestedElements() != 1) {
    ADD_FAILURE() << file << " is not a VTK collection";
    return out;
  }
  vtkXMLDataElement* coll = root->GetNestedElement(0);
  EXPECT_STREQ(coll->GetName(), "Collection");
  for (int i = 0; i < coll->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* ds = coll->GetNestedElement(i);
    EXPECT_STREQ(ds->GetName(), "DataSet");
    const char* t = ds->GetAttribute("timestep");
    const char* p = ds->GetAttribute("part");
    const char* f = ds->GetAttribute("file");
    if (!t || !f) {
      ADD_FAILURE() << file << ": DataSet " << i << " without timestep or file";
      continue;
    }
    out.push_back({std::stod(t), p ? std::stoi(p) : 0, f});
  }
  return out;
}

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name) const {
    auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
};

Csv read_csv(const fs::path& file) {
  Csv csv;
  const auto lines = lines_of(slurp(file));
  if (lines.empty()) {
    ADD_FAILURE() << file << " is empty";
    return csv;
  }
  csv.header = split(lines[0], ',');
  for (std::size_t k = 1; k < lines.size(); ++k) {
    if (lines[k].empty()) continue;
    const auto cells = split(lines[k], ',');
    EXPECT_EQ(cells.size(), csv.header.size()) << file << " row " << k << ": " << lines[k];
    std::vector<double> row;
    for (const auto& c : cells) {
      std::size_t used = 0;
      double v = std::nan("");
      try {
        v = std::stod(c, &used);
      } catch (const std::exception&) {
      }
      EXPECT_EQ(used, c.size()) << file << " row " << k << ": '" << c << "' is not a number";
      row.push_back(v);
    }
    csv.rows.push_back(std::move(row));
  }
  return csv;
}

std::set<std::string> point_array_names(vtkUnstructuredGrid* grid) {
  std::set<std::string> names;
  vtkPointData* pd = grid->GetPointData();
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
    if (pd->GetArrayName(i)) names.insert(pd->GetArrayName(i));
  return names;
}

/// Asserts an input error: exit 2, nothing on stdout, exactly one stderr line, starting with
/// "error: FILE at POINTER: " (or "error: FILE: " when pointer is empty), containing `needles`.
void expect_input_error(const Result& r, const std::string& file, const std::string& pointer,
                        const std::vector<std::string>& needles) {
  EXPECT_EQ(r.code, 2) << describe(r);
  EXPECT_EQ(r.out, "") << describe(r);
  const auto lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << "expected exactly one line on stderr\n" << describe(r);
  const std::string& line = lines[0];
  const std::string prefix = "error: " + file + (pointer.empty() ? ": " : " at " + pointer + ": ");
  EXPECT_EQ(line.rfind(prefix, 0), 0u) << "expected the line to start with '" << prefix << "'\n" << line;
  for (const auto& n : needles) EXPECT_TRUE(contains(line, n)) << "missing '" << n << "' in\n" << line;
  for (const char* bad : {"terminate called", "what():", "Aborted", "core dumped", "Traceback", "std::"})
    EXPECT_FALSE(contains(r.err, bad)) << r.err;
}

/// Writes the quick case, modified by `edit`, to `file`.
void write_case(const fs::path& file, const std::function<void(json&)>& edit) {
  json doc = read_json(kQuickCase);
  edit(doc);
  std::ofstream(file) << doc.dump(2) << "\n";
}

}  // namespace

// --- a run and its output contract ------------------------------------------------------------

TEST_F(Cli, QuickCaseRunWritesTheOutputContract) {
  const fs::path out = root() / "out";
  // Geometry and density pinned here, so that the expectations below do not depend on how the
  // bundled case is tuned.
  const Result r = run({"run", kQuickCase, "--set", "run.max_steps=300", "--set", "run.output_interval=0.005",
                        "--set", "process.billet_height=10 mm", "--set", "material.density=1e7 kg/m^3",
                        "--quiet", "--out", out.string()});
  ASSERT_EQ(r.code, 0) << describe(r);
  EXPECT_EQ(r.out, "") << "--quiet must print nothing";
  EXPECT_EQ(r.err, "") << "--quiet must print nothing";
  EXPECT_TRUE(fs::is_empty(work())) << "nothing may be written outside --out";

  // summary.json: every key of the contract.
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  const json summary = read_json(out / "summary.json");
  for (const char* key : {"case", "status", "particles", "steps", "simulated_time_s", "wall_time_s",
                          "particle_steps_per_s", "metrics", "versions"})
    EXPECT_TRUE(summary.contains(key)) << key << " missing from " << summary.dump(2);
  EXPECT_EQ(summary.value("case", ""), "paste_orifice_quick");
  EXPECT_EQ(summary.value("status", ""), "max_steps");
  EXPECT_EQ(summary.value("steps", -1), 300);
  // 13 layers (10 mm / 0.75 mm) of 820 lattice columns (0.75 mm spacing inside r <= 12.125 mm).
  const long long particles = summary.value("particles", -1LL);
  EXPECT_EQ(particles, 13 * 820);
  const double sim_time = summary.value("simulated_time_s", -1.0);
  const double wall = summary.value("wall_time_s", -1.0);
  EXPECT_GT(sim_time, 0.0);
  EXPECT_LT(sim_time, 1.0);  // stopped by max_steps long before end_time
  EXPECT_GT(wall, 0.0);
  EXPECT_NEAR(summary.value("particle_steps_per_s", -1.0), double(particles) * 300.0 / wall,
              1e-6 * double(particles) * 300.0 / wall);
  ASSERT_TRUE(summary["metrics"].is_object());
  EXPECT_FALSE(summary["metrics"].empty());
  EXPECT_GT(summary["metrics"].value("peak_extrusion_pressure_Pa", 0.0), 0.0) << summary["metrics"].dump();
  ASSERT_TRUE(summary["versions"].is_object());
  EXPECT_TRUE(summary["versions"].contains("core"));
  EXPECT_TRUE(summary["versions"]["core"].is_string());
  ASSERT_TRUE(summary["versions"].contains("plugins"));
  for (const char* p : {"elastoplastic", "coulomb", "prescribed", "ram_extrusion"})
    EXPECT_TRUE(summary["versions"]["plugins"].contains(p)) << p << " missing from " << summary["versions"].dump();

  // particles.pvd + .vtu: every frame reads with VTK, has every particle and the right fields.
  const auto frames = read_pvd(out / "particles.pvd");
  ASSERT_GE(frames.size(), 3u);  // t = 0, 0.005, 0.010 at least
  EXPECT_EQ(frames.front().time, 0.0);
  EXPECT_DOUBLE_EQ(frames.back().time, sim_time);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE(frames[k].file);
    if (k > 0) EXPECT_GT(frames[k].time, frames[k - 1].time) << "frame times must increase";
    ASSERT_TRUE(fs::exists(out / frames[k].file));
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName((out / frames[k].file).string().c_str());
    reader->Update();
    ASSERT_EQ(reader->GetErrorCode(), 0);
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_NE(grid, nullptr);
    EXPECT_EQ(grid->GetNumberOfPoints(), particles);
    const auto names = point_array_names(grid);
    for (const char* n : {"velocity", "pressure", "deviatoric_stress", "density", "plastic_strain"})
      EXPECT_EQ(names.count(n), 1u) << n;
    EXPECT_EQ(names.count("temperature"), 0u) << "an isothermal run has no temperature";
    vtkPointData* pd = grid->GetPointData();
    if (auto* s = pd->GetArray("deviatoric_stress")) EXPECT_EQ(s->GetNumberOfComponents(), 6);
    if (auto* v = pd->GetArray("velocity")) EXPECT_EQ(v->GetNumberOfComponents(), 3);
    if (auto* d = pd->GetArray("density")) {
      EXPECT_EQ(d->GetNumberOfComponents(), 1);
      double range[2];
      d->GetRange(range, 0);
      EXPECT_GT(range[0], 0.9e7);  // rho0 = 1e7 kg/m^3, nearly incompressible paste
      EXPECT_LT(range[1], 1.1e7);
    }
    if (auto* t = grid->GetFieldData()->GetArray("TimeValue")) EXPECT_DOUBLE_EQ(t->GetComponent(0, 0), frames[k].time);
  }

  // tools.pvd: barrel, die and ram .vtp in every frame, readable with VTK; the ram moved down.
  const auto tools = read_pvd(out / "tools.pvd");
  ASSERT_EQ(tools.size(), 3 * frames.size());
  std::map<double, std::set<std::string>> tools_at;
  double ram_z_first = NAN, ram_z_last = NAN;
  for (const auto& t : tools) {
    SCOPED_TRACE(t.file);
    const std::string tool = t.file.substr(t.file.rfind('_') + 1);  // "barrel.vtp"
    tools_at[t.time].insert(tool);
    ASSERT_TRUE(fs::exists(out / t.file));
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((out / t.file).string().c_str());
    reader->Update();
    ASSERT_EQ(reader->GetErrorCode(), 0);
    vtkPolyData* poly = reader->GetOutput();
    EXPECT_GT(poly->GetNumberOfPoints(), 0);
    EXPECT_GT(poly->GetNumberOfPolys(), 0);
    if (tool == "ram.vtp") {
      double b[6];
      poly->GetBounds(b);
      EXPECT_DOUBLE_EQ(b[4], b[5]) << "the ram face is flat";
      if (t.time == frames.front().time) ram_z_first = b[4];
      if (t.time == frames.back().time) ram_z_last = b[4];
    }
  }
  EXPECT_EQ(tools_at.size(), frames.size());
  for (const auto& [time, names] : tools_at)
    EXPECT_EQ(names, (std::set<std::string>{"barrel.vtp", "die.vtp", "ram.vtp"})) << "t = " << time;
  EXPECT_NEAR(ram_z_first, 9.75e-3, 1e-12);  // the ram starts on the billet top (13 layers of 0.75 mm)
  EXPECT_NEAR(ram_z_first - ram_z_last, summary["metrics"].value("final_ram_displacement_m", -1.0), 1e-12);
  EXPECT_NEAR(ram_z_first - ram_z_last, 1e-3 * sim_time, 1e-9);  // 1 mm/s

  // history.csv: units on every column, rows complete, time increasing, the ram pushes.
  const Csv csv = read_csv(out / "history.csv");
  ASSERT_FALSE(csv.header.empty());
  EXPECT_EQ(csv.header[0], "time_s");
  const std::regex unit_suffix("_(s|m|N|Pa|J|Nm|m_s|1|kg|K|W|rad)$");
  for (const auto& name : csv.header) EXPECT_TRUE(std::regex_search(name, unit_suffix)) << "no unit: " << name;
  const int force = csv.column("ram_force_N"), pressure = csv.column("extrusion_pressure_Pa");
  ASSERT_GE(force, 0);
  ASSERT_GE(pressure, 0);
  ASSERT_GE(csv.rows.size(), 10u);  // history every output_interval/10
  EXPECT_EQ(csv.rows.front()[0], 0.0);
  EXPECT_DOUBLE_EQ(csv.rows.back()[0], sim_time);
  for (std::size_t k = 1; k < csv.rows.size(); ++k)
    EXPECT_GT(csv.rows[k][0], csv.rows[k - 1][0]) << "row " << k + 1 << ": time must increase strictly";
  const bool pushes = std::any_of(csv.rows.begin(), csv.rows.end(), [&](const auto& row) { return row[force] > 0.0; });
  EXPECT_TRUE(pushes) << "the ram force never became positive";
  EXPECT_GT(csv.rows.back()[force], 0.0);
  EXPECT_GT(csv.rows.back()[pressure], 0.0);
  // P_ex = F / (pi R0^2), R0 = 12.5 mm.
  EXPECT_NEAR(csv.rows.back()[pressure], csv.rows.back()[force] / (std::numbers::pi * 12.5e-3 * 12.5e-3),
              1e-9 * std::abs(csv.rows.back()[pressure]));
}

TEST_F(Cli, PhasesSwitchOnASignalAndOnTimeAndEndTheRun) {
  // The quick case's ram: pushes at 1 mm/s until it has moved 0.05 mm, holds for 0.02 s, then
  // accelerates as a schedule written in phase time (0 -> 2 mm/s over 0.02 s) for 0.03 s, which
  // ends the run before run.end_time (docs/controllers.md, theory eq. 65).
  const fs::path file = root() / "phases.json";
  write_case(file, [](json& c) {
    c.erase("controllers");
    auto prescribed = [](const char* v) { return json{{"plugin", "prescribed"}, {"command", "ram_velocity"}, {"value", v}}; };
    c["phases"] = json::array(
        {json{{"name", "push"}, {"controllers", json::array({prescribed("1 mm/s")})},
              {"end", {{"signal", "ram_displacement"}, {"above", "0.05 mm"}}}},
         json{{"name", "hold"}, {"controllers", json::array({prescribed("0 mm/s")})}, {"end", {{"duration", "0.02 s"}}}},
         json{{"name", "ramp"},
              {"controllers", json::array({json{{"plugin", "schedule"}, {"command", "ram_velocity"},
                                                {"points", json::array({json::array({"0 s", "0 mm/s"}),
                                                                        json::array({"0.02 s", "2 mm/s"})})}}})},
              {"end", {{"duration", "0.03 s"}}}}});
    c["run"]["end_time"] = "1 s";
    c["run"]["output_interval"] = "1 s";
  });
  const fs::path out = root() / "out";
  const Result r = run({"run", file.string(), "--out", out.string(), "--quiet"});
  ASSERT_EQ(r.code, 0) << describe(r);
  const json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary.value("status", ""), "phases_ended");
  ASSERT_TRUE(summary.contains("phases")) << summary.dump(2);
  const json& ph = summary["phases"];
  ASSERT_EQ(ph.size(), 3u);
  const double t1 = ph[0]["end_s"].get<double>(), t2 = ph[1]["end_s"].get<double>(), t3 = ph[2]["end_s"].get<double>();
  EXPECT_EQ(ph[1]["start_s"].get<double>(), t1);
  EXPECT_EQ(ph[2]["start_s"].get<double>(), t2);

  const Csv csv = read_csv(out / "history.csv");
  const int time = csv.column("time_s"), dt = csv.column("dt_s"), phase = csv.column("phase_1"),
            disp = csv.column("ram_displacement_m"), vel = csv.column("ram_velocity_m_s");
  ASSERT_TRUE(time >= 0 && dt >= 0 && phase >= 0 && disp >= 0 && vel >= 0) << "missing columns";
  const double step = csv.rows.back()[dt];
  // The push ends at the first step whose displacement exceeds 0.05 mm: t1 = 0.05 s within a step.
  EXPECT_NEAR(t1, 0.05, 1.5 * step);
  EXPECT_NEAR(t2 - t1, 0.02, 1.5 * step);
  EXPECT_NEAR(t3 - t2, 0.03, 1.5 * step);
  EXPECT_NEAR(summary["simulated_time_s"].get<double>(), t3, 1.5 * step);
  for (const auto& row : csv.rows) {
    const double t = row[time];
    SCOPED_TRACE("t = " + std::to_string(t));
    if (t == 0.0) continue;  // the first row is written before the controllers' first update
    if (t < t1 - 1e-12) {
      EXPECT_EQ(row[phase], 1.0);
      EXPECT_EQ(row[vel], 1e-3);
    } else if (t > t1 + 1e-12 && t < t2 - 1e-12) {
      EXPECT_EQ(row[phase], 2.0);
      EXPECT_EQ(row[vel], 0.0);
      EXPECT_NEAR(row[disp], 5e-5, 1e-3 * step);  // held: moved by at most one step past 0.05 mm
    } else if (t > t2 + 1e-12 && t < t3 - 1e-12) {
      EXPECT_EQ(row[phase], 3.0);
      // Phase time t - t2, the schedule's ramp of 0.1 m/s^2, held over the step since the update.
      EXPECT_NEAR(row[vel], 0.1 * std::min(t - t2, 0.02), 0.1 * 1.5 * step);
    }
  }
}

TEST_F(Cli, FinalHistoryRowAndFrameAreNotDuplicated) {
  // With history and frames due on almost every step, the last step has just written both: the
  // end of the run must not write them a second time at the same time.
  const fs::path out = root() / "out";
  const Result r = run(concat({"run", kQuickCase, "--set", "run.max_steps=20", "--set", "run.output_interval=0.0001",
                               "--quiet", "--out", out.string()},
                              kTinyCase));
  ASSERT_EQ(r.code, 0) << describe(r);
  const Csv csv = read_csv(out / "history.csv");
  ASSERT_GE(csv.rows.size(), 2u);
  for (std::size_t k = 1; k < csv.rows.size(); ++k)
    EXPECT_GT(csv.rows[k][0], csv.rows[k - 1][0]) << "history row " << k + 1 << " repeats time " << csv.rows[k][0];
  const auto frames = read_pvd(out / "particles.pvd");
  ASSERT_GE(frames.size(), 2u);
  for (std::size_t k = 1; k < frames.size(); ++k)
    EXPECT_GT(frames[k].time, frames[k - 1].time) << frames[k].file << " repeats time " << frames[k].time;
  const auto tools = read_pvd(out / "tools.pvd");
  EXPECT_EQ(tools.size(), 3 * frames.size());
}

// --- restart checkpoints (docs/checkpoints.md) -------------------------------------------------

TEST_F(Cli, RestartFromACheckpointRepeatsTheUninterruptedRunExactly) {
  // The tiny scene with a PID on the ram (integral, sampling instants and held command) and Coulomb
  // friction (the friction laws' memory), so that the plugins' restart state is exercised. One
  // thread: OpenMP's sum reductions combine partial sums in arrival order, which would make even
  // two uninterrupted runs differ in the last bits.
  const std::string pid =
      R"({"plugin": "pid", "name": "ram_pid", "measured": "ram_force", "command": "ram_velocity",)"
      R"( "target": "300 N", "kp": "2e-6 m/s/N", "ki": "2e-5 m/s/N/s", "kd": "0 m/N",)"
      R"( "command_limits": ["0 mm/s", "3 mm/s"], "sample_interval": "0.002 s"})";
  const std::vector<std::string> scene =
      concat({"--set", "controllers.0=" + pid, "--set", "run.threads=1", "--set", "run.end_time=0.06 s", "--set",
              "run.output_interval=0.01 s", "--set", "run.history_interval=0.001 s", "--quiet"},
             kTinyCase);
  const fs::path a = root() / "a", b = root() / "b", c = root() / "c";
  // The command of the interrupted run again, with --restart (so the restarted run also checkpoints,
  // and rebuilds its neighbour lists after each checkpoint as the uninterrupted one does).
  const std::vector<std::string> checkpoints = concat(scene, {"--set", "run.checkpoint_interval=0.025 s"});
  Result r = run(concat({"run", kQuickCase, "--out", a.string()}, checkpoints));
  ASSERT_EQ(r.code, 0) << describe(r);
  // At 0.025 s and 0.05 s, and one at the end.
  for (const char* f : {"checkpoint_000000.h5", "checkpoint_000001.h5", "checkpoint_000002.h5"})
    ASSERT_TRUE(fs::is_regular_file(a / f)) << f;
  EXPECT_FALSE(fs::exists(a / "checkpoint_000003.h5"));
  const json sa = json::parse(slurp(a / "summary.json"));
  EXPECT_EQ(sa.at("checkpoints"), 3);

  r = run(concat({"run", kQuickCase, "--out", b.string(), "--restart", (a / "checkpoint_000000.h5").string()},
                 checkpoints));
  ASSERT_EQ(r.code, 0) << describe(r);
  const json sb = json::parse(slurp(b / "summary.json"));
  const long long restart_step = sb.at("restart").at("step").get<long long>();
  EXPECT_GT(restart_step, 0);
  EXPECT_LT(restart_step, sa.at("steps").get<long long>() / 2 + 10);
  EXPECT_GE(sb.at("restart").at("time_s").get<double>(), 0.025);
  EXPECT_GT(sb.at("restart").at("history_rows_copied").get<int>(), 20);
  // Step for step the same run: every history row (copied up to the checkpoint, computed after it)
  // to the last bit of its %.17g text, and the same process metrics, steps and frames.
  const std::string ha = slurp(a / "history.csv"), hb = slurp(b / "history.csv");
  EXPECT_GT(lines_of(ha).size(), 50u);
  EXPECT_EQ(ha, hb);
  EXPECT_EQ(sb.at("metrics"), sa.at("metrics"));
  EXPECT_EQ(sb.at("steps"), sa.at("steps"));
  EXPECT_EQ(sb.at("simulated_time_s"), sa.at("simulated_time_s"));
  EXPECT_EQ(sb.at("frames"), sa.at("frames"));
  EXPECT_EQ(sb.at("kinetic_to_work_ratio_max"), sa.at("kinetic_to_work_ratio_max"));
  // The new folder numbers its frames on from the checkpoint's and lists the earlier ones by their
  // path in the earlier folder, so its .pvd files show the whole run; the last frame is the same state.
  const auto fa = read_pvd(a / "particles.pvd"), fb = read_pvd(b / "particles.pvd");
  ASSERT_EQ(fb.size(), fa.size());
  for (std::size_t k = 0; k < fa.size(); ++k) {
    EXPECT_EQ(fb[k].time, fa[k].time);
    const bool earlier = fa[k].time <= sb.at("restart").at("time_s").get<double>();
    EXPECT_EQ(fb[k].file, earlier ? "../a/" + fa[k].file : fa[k].file);
    EXPECT_TRUE(fs::is_regular_file(b / fb[k].file)) << fb[k].file;
  }
  EXPECT_EQ(read_pvd(b / "tools.pvd").size(), read_pvd(a / "tools.pvd").size());
  EXPECT_TRUE(slurp(b / fb.back().file) == slurp(a / fa.back().file)) << "the last frames differ";
  // It numbers its checkpoints on from the one it started from.
  EXPECT_FALSE(fs::exists(b / "checkpoint_000000.h5"));
  EXPECT_TRUE(fs::is_regular_file(b / "checkpoint_000001.h5"));
  EXPECT_TRUE(fs::is_regular_file(b / "checkpoint_000002.h5"));

  // A finished run goes on from its last checkpoint with a later end time, and a changed checkpoint
  // interval starts its grid at the checkpoint (0.064 and 0.068 s, then the final one at 0.07 s;
  // on the old grid the next would have been 0.075 s).
  r = run(concat({"run", kQuickCase, "--out", c.string(), "--restart", (a / "checkpoint_000002.h5").string()},
                 concat(scene, {"--set", "run.end_time=0.07 s", "--set", "run.checkpoint_interval=0.004 s"})));
  ASSERT_EQ(r.code, 0) << describe(r);
  const json sc = json::parse(slurp(c / "summary.json"));
  EXPECT_GT(sc.at("steps").get<long long>(), sa.at("steps").get<long long>());
  EXPECT_NEAR(sc.at("simulated_time_s").get<double>(), 0.07, 1e-4);
  EXPECT_EQ(sc.at("checkpoints"), 6);
  for (const char* f : {"checkpoint_000003.h5", "checkpoint_000004.h5", "checkpoint_000005.h5"})
    EXPECT_TRUE(fs::is_regular_file(c / f)) << f;
}

TEST_F(Cli, RestartRepeatsTheRunForEveryProcessPlugin) {
  // Each process's own restart state (samples and peaks, bushing and maxima, probes and extents),
  // with what the scenes add: phases with a PID (friction extrusion), thermal bodies attached to a
  // rotating tool and the thermal pass's properties (eq. 26 time step), material separation.
  struct Scene {
    std::string file;
    std::vector<std::string> sets;
  };
  const std::string src = SPHFORGE_SOURCE_DIR;
  const std::vector<Scene> scenes = {
      {src + "/cases/friction_extrusion/aa7075_pid_300kN_phases.json",
       {"run.end_time=0.012 s", "run.history_interval=0.0005 s", "run.checkpoint_interval=0.005 s"}},
      {src + "/cases/friction_drilling/hx220_m4_quick.json",
       {"run.end_time=1e-4 s", "run.history_interval=2e-6 s", "run.checkpoint_interval=4e-5 s"}},
      {src + "/cases/verification/tool_heat_rotating_die.json",
       {"run.end_time=2 ms", "run.history_interval=0.02 ms", "run.checkpoint_interval=0.7 ms"}},
      // Sub-cycled thermal pass (eq. 26b): a checkpoint between two thermal steps holds the time since
      // the last one and the die's pending share of the friction heat (45 mechanical steps per thermal step).
      {src + "/cases/verification/tool_heat_rotating_die.json",
       {"thermal.subcycling=true", "thermal.time_step_factor=0.001", "run.end_time=2 ms",
        "run.history_interval=0.02 ms", "run.checkpoint_interval=0.7 ms"}},
      // The same scene with a Johnson-Cook disc whose conductivity grows with temperature and makes
      // conduction limit the time step (dt_thermal 0.338 us against dt_cfl 1.5 us): the first step
      // after the restart is sized by the properties of the last thermal pass (eq. 26), which only
      // the checkpoint holds (a rebuilt scene evaluates them at the initial temperature). Dropping
      // their restore makes history.csv differ (checked by mutation).
      {src + "/cases/verification/tool_heat_rotating_die.json",
       {R"j(material={"plugin":"johnson_cook","density":"1000 kg/m^3","youngs_modulus":"200 MPa",)j"
        R"j("poisson_ratio":0.3,"A":"1 MPa","B":"0 MPa","n":1,"C":0,"m":1,"reference_temperature":"300 K",)j"
        R"j("melting_temperature":"1300 K","conductivity":"1e6 W/(m*K)","conductivity_slope":"1e6 W/(m*K)",)j"
        R"j("specific_heat":"500 J/(kg*K)"})j",
        "run.end_time=0.3 ms", "run.history_interval=0.01 ms", "run.checkpoint_interval=0.1 ms"}},
  };
  int k = 0;
  for (const Scene& scene : scenes) {
    SCOPED_TRACE(scene.file);
    std::vector<std::string> args = {"--quiet", "--set", "run.threads=1"};
    for (const std::string& set : scene.sets) args = concat(args, {"--set", set});
    const fs::path a = root() / ("a" + std::to_string(k)), b = root() / ("b" + std::to_string(k));
    ++k;
    Result r = run(concat({"run", scene.file, "--out", a.string()}, args));
    ASSERT_EQ(r.code, 0) << describe(r);
    r = run(concat({"run", scene.file, "--out", b.string(), "--restart", (a / "checkpoint_000000.h5").string()}, args));
    ASSERT_EQ(r.code, 0) << describe(r);
    const json sa = json::parse(slurp(a / "summary.json")), sb = json::parse(slurp(b / "summary.json"));
    EXPECT_GT(sb.at("restart").at("step").get<long long>(), 10);
    EXPECT_GT(sb.at("steps").get<long long>(), sb.at("restart").at("step").get<long long>() + 10);
    EXPECT_TRUE(slurp(a / "history.csv") == slurp(b / "history.csv")) << "history.csv differs";
    EXPECT_EQ(sb.at("metrics"), sa.at("metrics"));
    EXPECT_EQ(sb.at("steps"), sa.at("steps"));
    if (sa.contains("phases")) EXPECT_EQ(sb.at("phases"), sa.at("phases"));
  }
}

TEST_F(Cli, RestartIsRefusedForAnotherCaseAndAFileThatIsNoCheckpoint) {
  const fs::path a = root() / "a";
  Result r = run(concat({"run", kQuickCase, "--quiet", "--out", a.string(), "--set", "run.max_steps=5", "--set",
                         "run.checkpoint_interval=1e-9 s"},
                        kTinyCase));
  ASSERT_EQ(r.code, 0) << describe(r);
  const std::string checkpoint = (a / "checkpoint_000000.h5").string();
  ASSERT_TRUE(fs::is_regular_file(checkpoint));
  // Another scene: only "run" may change.
  r = run(concat({"run", kQuickCase, "--restart", checkpoint, "--set", "process.stroke=2 mm"}, kTinyCase));
  expect_input_error(r, kQuickCase, "/process/stroke", {"differs from the case that wrote", checkpoint});
  // Not a checkpoint.
  r = run(concat({"run", kQuickCase, "--restart", kQuickCase}, kTinyCase));
  expect_input_error(r, kQuickCase, "", {"cannot restart from this file"});
  r = run(concat({"run", kQuickCase, "--restart", (a / "missing.h5").string()}, kTinyCase));
  expect_input_error(r, (a / "missing.h5").string(), "", {"no such file"});
  // A plugin without restart state: tests/unit/test_checkpoint.cpp (a test-only process).
  EXPECT_TRUE(fs::is_empty(work()));
}

// --- the executable links no plugin -----------------------------------------------------------

TEST(CliLinking, ExecutableAndCoreLinkNoPlugin) {
  auto ldd = [](const std::string& file) {
    std::string text;
    FILE* pipe = ::popen(("ldd " + shell_quote(file) + " 2>&1").c_str(), "r");
    if (!pipe) {
      ADD_FAILURE() << "cannot run ldd";
      return text;
    }
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) text.append(buf, n);
    const int status = ::pclose(pipe);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "ldd " << file << ":\n" << text;
    return text;
  };
  const std::string exe = ldd(kExe), core = ldd(kCoreLibrary);
  // The output is really parsed: the executable links the core, and both link the C library.
  bool exe_has_core = false;
  for (const auto& line : lines_of(exe)) exe_has_core = exe_has_core || contains(line, "libsphforge_core");
  EXPECT_TRUE(exe_has_core) << exe;
  EXPECT_TRUE(contains(exe, "libc.so")) << exe;
  EXPECT_TRUE(contains(core, "libc.so")) << core;
  for (const auto& [name, text] : {std::pair{kExe, exe}, std::pair{kCoreLibrary, core}})
    for (const auto& line : lines_of(text))
      for (const char* plugin :
           {"sphforge_elastoplastic", "sphforge_coulomb", "sphforge_prescribed", "sphforge_ram_extrusion", "plugins/"})
        EXPECT_FALSE(contains(line, plugin)) << name << " links a plugin: " << line;
}

// --- invalid input: exit 2, one located message, no output folder ---------------------------

class CliInput : public Cli {
 protected:
  /// Writes the quick case modified by `edit`, runs it, expects an input error at `pointer`.
  void expect_rejected(const std::function<void(json&)>& edit, const std::string& pointer,
                       const std::vector<std::string>& needles) {
    const fs::path file = root() / "case.json";
    write_case(file, edit);
    const fs::path out = root() / "out";
    // max_steps keeps a wrongly accepted case short; it fails the test by its exit code.
    const Result r = run({"run", file.string(), "--set", "run.max_steps=2", "--out", out.string()});
    expect_input_error(r, file.string(), pointer, needles);
    EXPECT_FALSE(fs::exists(out)) << "the output folder must not be created for invalid input";
    EXPECT_TRUE(fs::is_empty(work()));
  }
};

TEST_F(CliInput, UnknownKey) {
  expect_rejected([](json& c) { c["material"]["foo"] = 1; }, "/material/foo", {"unknown key 'foo'", "yield_stress"});
}

TEST_F(CliInput, WrongUnit) {
  expect_rejected([](json& c) { c["material"]["yield_stress"] = "0.38 m"; }, "/material/yield_stress",
                  {"Pa", "0.38 m"});
}

TEST_F(CliInput, MissingValue) {
  expect_rejected([](json& c) { c["material"].erase("yield_stress"); }, "/material/yield_stress",
                  {"missing", "yield_stress"});
}

TEST_F(CliInput, OutOfRange) {
  expect_rejected([](json& c) { c["material"]["poisson_ratio"] = 0.7; }, "/material/poisson_ratio",
                  {"0.7", "range", "0.4999"});
}

TEST_F(CliInput, UnknownPluginName) {
  expect_rejected([](json& c) { c["contact"]["law"]["plugin"] = "nope"; }, "/contact/law/plugin",
                  {"unknown contact plugin 'nope'", "coulomb"});
}

TEST_F(CliInput, UnknownControllerCommand) {
  expect_rejected([](json& c) { c["controllers"][0]["command"] = "spin"; }, "/controllers/0/command",
                  {"'spin'", "ram_velocity"});
}

TEST_F(CliInput, ControllerValueWithWrongUnit) {
  expect_rejected([](json& c) { c["controllers"][0]["value"] = "1 kN"; }, "/controllers/0/value",
                  {"m/s", "1 kN"});
}

/// The quick case's ram driven by a PID on the ram force instead of the prescribed velocity.
json ram_force_pid() {
  return {{"plugin", "pid"}, {"name", "ram_pid"}, {"measured", "ram_force"}, {"command", "ram_velocity"},
          {"target", "200 N"}, {"kp", "0.01 mm/s/N"}, {"ki", "0.05 mm/s/N/s"}, {"kd", "0 mm/N"}};
}

TEST_F(CliInput, PidWithUnknownMeasuredSignalListsTheSignals) {
  expect_rejected(
      [](json& c) {
        c["controllers"][0] = ram_force_pid();
        c["controllers"][0]["measured"] = "die_force_z";
      },
      "/controllers/0/measured", {"'die_force_z'", "ram_force", "ram_displacement", "extrusion_pressure"});
}

TEST_F(CliInput, PidGainForAnotherQuantityIsRefusedByItsUnit) {
  // A gain meant for a rotation speed (rpm per kN) cannot drive the ram velocity.
  expect_rejected(
      [](json& c) {
        c["controllers"][0] = ram_force_pid();
        c["controllers"][0]["kp"] = "0.015 rpm/kN";
      },
      "/controllers/0/kp", {"0.015 rpm/kN", "(m/s)/(N)"});
}

TEST_F(CliInput, CheckRejectsABadControllerBeforeAnyRun) {
  const fs::path file = root() / "case.json";
  write_case(file, [](json& c) {
    c["controllers"][0] = ram_force_pid();
    c["controllers"][0]["command"] = "die_angular_velocity";
  });
  expect_input_error(run({"check", file.string()}), file.string(), "/controllers/0/command",
                     {"'die_angular_velocity'", "ram_velocity"});
}

TEST_F(CliInput, ScheduleOfAnUnknownCommand) {
  expect_rejected(
      [](json& c) {
        c["controllers"] = json::array({json{{"plugin", "schedule"}, {"command", "pid_target"},
                                             {"points", json::array({json::array({"0 s", "1 mm/s"})})}}});
      },
      "/controllers/0/command", {"'pid_target'", "ram_velocity"});
}

TEST_F(CliInput, PhaseWithoutEndThatIsNotTheLast) {
  expect_rejected(
      [](json& c) {
        const json ctl = c["controllers"];
        c.erase("controllers");
        c["phases"] = json::array({json{{"name", "a"}, {"controllers", ctl}}, json{{"name", "b"}, {"controllers", ctl}}});
      },
      "/phases/0/end", {"only the last phase"});
}

TEST_F(CliInput, PhaseEndOnAnUnknownSignal) {
  expect_rejected(
      [](json& c) {
        c["phases"] = json::array({json{{"name", "a"}, {"end", {{"signal", "force"}, {"above", "1 N"}}}}});
      },
      "/phases/0/end/signal", {"'force'", "ram_force"});
}

TEST_F(CliInput, MalformedJson) {
  const fs::path file = root() / "truncated.json";
  const std::string text = slurp(kQuickCase);
  ASSERT_GT(text.size(), 100u);
  std::ofstream(file) << text.substr(0, text.size() / 2);
  const fs::path out = root() / "out";
  const Result r = run({"run", file.string(), "--out", out.string()});
  expect_input_error(r, file.string(), "", {"JSON", "line "});
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliInput, MissingCaseFile) {
  const fs::path file = root() / "no_such_case.json";
  const fs::path out = root() / "out";
  const Result r = run({"run", file.string(), "--out", out.string()});
  expect_input_error(r, file.string(), "", {"cannot open case file"});
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliInput, BadSetSyntax) {
  const fs::path out = root() / "out";
  const Result r = run({"run", kQuickCase, "--set", "run.max_steps", "--out", out.string()});
  expect_input_error(r, kQuickCase, "--set run.max_steps", {"key.path=value"});
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliInput, SetOfAnUnknownSection) {
  // --set creates missing objects on its way; validation then rejects a section that does not exist.
  const fs::path out = root() / "out";
  const Result r = run({"run", kQuickCase, "--set", "nosuch.section.value=1", "--out", out.string()});
  expect_input_error(r, kQuickCase, "/nosuch", {"unknown key 'nosuch'", "numerics"});
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliInput, SetIntoAValue) {
  const fs::path out = root() / "out";
  const Result r = run({"run", kQuickCase, "--set", "run.end_time.x=1", "--out", out.string()});
  expect_input_error(r, kQuickCase, "--set run.end_time.x", {"no object at /run/end_time"});
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliInput, UnknownOptionAndCommand) {
  const Result opt = run({"run", kQuickCase, "--frobnicate"});
  EXPECT_EQ(opt.code, 2) << describe(opt);
  EXPECT_TRUE(contains(opt.err, "error: ") && contains(opt.err, "--frobnicate")) << describe(opt);
  EXPECT_EQ(lines_of(opt.err).size(), 1u) << describe(opt);
  const Result cmd = run({"frobnicate"});
  EXPECT_EQ(cmd.code, 2) << describe(cmd);
  EXPECT_TRUE(contains(cmd.err, "unknown command 'frobnicate'")) << describe(cmd);
  EXPECT_TRUE(fs::is_empty(work()));
}

// --- a numerical blow-up: exit 3 ------------------------------------------------------------

TEST_F(Cli, DomainMarginBoundsHowFarParticlesMayGo) {
  // numerics.domain_margin = 0: the first particle that moves out of the initial bounding box (the
  // billet bulging under the ram, within the first check at step 10) stops the run with exit 3, and
  // the message names the option a long extrudate needs. The default (the scene's own size) lets
  // the same 20 steps complete.
  const fs::path tight = root() / "tight", loose = root() / "loose";
  const Result r = run(concat({"run", kQuickCase, "--set", "numerics.domain_margin=0 mm", "--set", "run.max_steps=20",
                               "--quiet", "--out", tight.string()},
                              kTinyCase));
  ASSERT_EQ(r.code, 3) << describe(r);
  EXPECT_TRUE(contains(r.err, "particle left the domain") && contains(r.err, "numerics.domain_margin")) << r.err;
  const Result ok = run(concat({"run", kQuickCase, "--set", "run.max_steps=20", "--quiet", "--out", loose.string()},
                               kTinyCase));
  EXPECT_EQ(ok.code, 0) << describe(ok);
}

TEST_F(Cli, InstabilityExitsWithThreeAndLocatesIt) {
  // cfl = 2 with a soft contact spring (whose time-step limit then no longer caps dt) and no
  // artificial viscosity is far beyond the leapfrog's stability limit: the energy ledger stops the
  // run within a few dozen steps (step 10 when last run), long before max_steps.
  const fs::path out = root() / "out";
  const Result r = run(concat({"run", kQuickCase, "--set", "numerics.cfl=2", "--set", "contact.stiffness_factor=0.001",
                               "--set", R"(numerics.artificial_viscosity={"alpha":0,"beta":0})", "--set",
                               "run.max_steps=300", "--quiet", "--out", out.string()},
                              kTinyCase));
  ASSERT_EQ(r.code, 3) << describe(r);
  const auto lines = lines_of(r.err);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << r.err;
  const std::regex located(R"(numerical instability at step (\d+), t = ([0-9.eE+-]+) s, particle (\d+), field '(\w+)')");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(lines[0], m, located)) << "message must name step, time, particle and field:\n"
                                                       << r.err;
  const long long step = std::stoll(m[1]);
  const double time = std::stod(m[2]);
  const long long particle = std::stoll(m[3]);
  const std::string field = m[4];
  EXPECT_GT(step, 0);
  EXPECT_LT(step, 300);
  EXPECT_GT(time, 0.0);
  EXPECT_GE(particle, 0);
  EXPECT_LT(particle, 1792);
  EXPECT_TRUE(field == "velocity" || field == "position" || field == "deviatoric_stress" || field == "density" ||
              field == "pressure")
      << field;
  for (const char* bad : {"terminate called", "what():", "Aborted"}) EXPECT_FALSE(contains(r.err, bad)) << r.err;

  // The summary records it, and the last state is there to look at.
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  const json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary.value("status", ""), "unstable");
  EXPECT_EQ(summary.value("steps", -1LL), step);
  EXPECT_TRUE(contains(summary.value("diagnosis", ""), "step " + std::to_string(step))) << summary.dump(2);
  EXPECT_FALSE(read_pvd(out / "particles.pvd").empty());
}

// --- check and plugins --------------------------------------------------------------------------

TEST_F(Cli, CheckAcceptsTheSecondOrderGradientAndRejectsBadCombinations) {
  // numerics.gradient_correction_order (docs/theory.md section 18): "first" or "second"; "second"
  // needs the first-order correction on and is not implemented with symmetry or bond failure.
  const std::string plate = std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/oscillating_plate.json";
  const Result second = run({"check", plate, "--set", "numerics.gradient_correction_order=second"});
  ASSERT_EQ(second.code, 0) << describe(second);
  EXPECT_TRUE(contains(second.out, "velocity_gradient_second_order")) << second.out;
  const Result third = run({"check", plate, "--set", "numerics.gradient_correction_order=third"});
  EXPECT_EQ(third.code, 2) << describe(third);
  EXPECT_TRUE(contains(third.err, "/numerics/gradient_correction_order")) << third.err;
  const Result off = run({"check", plate, "--set", "numerics.gradient_correction_order=second", "--set",
                          "numerics.gradient_correction=false"});
  EXPECT_EQ(off.code, 2) << describe(off);
  EXPECT_TRUE(contains(off.err, "/numerics/gradient_correction_order")) << off.err;
  EXPECT_TRUE(contains(off.err, "needs numerics.gradient_correction = true")) << off.err;
  // The plain and deviatoric momentum terms (eqs. 7a, 7b) replace eq. 7 only; the second order has its
  // own (eq. 136). A value that is not one of the three is refused at its pointer too.
  for (const char* mode : {"none", "deviatoric", "partial"}) {
    const Result plain = run({"check", plate, "--set", "numerics.gradient_correction_order=second", "--set",
                              std::string("numerics.momentum_correction=") + mode});
    EXPECT_EQ(plain.code, 2) << mode << ": " << describe(plain);
    EXPECT_TRUE(contains(plain.err, "/numerics/momentum_correction")) << mode << ": " << plain.err;
  }
  const std::string cylinder =
      std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/spinning_compressed_cylinder.json";
  const Result sym = run({"check", cylinder, "--set", "numerics.symmetry.sector.angle=90 deg", "--set",
                          "numerics.gradient_correction_order=second"});
  EXPECT_EQ(sym.code, 2) << describe(sym);
  EXPECT_TRUE(contains(sym.err, "/numerics/gradient_correction_order")) << sym.err;
}

TEST_F(Cli, DensityDiffusionIsAPassOnlyWhenOnAndNeedsOneMaterial) {
  // numerics.density_diffusion (docs/theory.md eq. 4a): the paste cases set 0.1, so the quick case
  // lists the pass; 0 removes it; two mechanical materials are refused with the pointer.
  const Result on = run({"check", kQuickCase});
  ASSERT_EQ(on.code, 0) << describe(on);
  EXPECT_TRUE(contains(on.out, "  density_diffusion\n")) << on.out;
  const Result off = run({"check", kQuickCase, "--set", "numerics.density_diffusion=0"});
  ASSERT_EQ(off.code, 0) << describe(off);
  EXPECT_FALSE(contains(off.out, "density_diffusion")) << off.out;
  const std::string series = std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/two_material_series.json";
  const Result two = run({"check", series, "--set", "process.bodies.0.mechanics=true", "--set",
                          "process.bodies.1.mechanics=true", "--set", "numerics.density_diffusion=0.1"});
  EXPECT_EQ(two.code, 2) << describe(two);
  EXPECT_TRUE(contains(two.err, "/numerics/density_diffusion")) << two.err;
  EXPECT_TRUE(contains(two.err, "needs one material for all mechanical bodies; this case has 2")) << two.err;
}

TEST_F(Cli, CheckClipsTheSceneToTheSymmetryRegionAndRejectsBadSymmetry) {
  // numerics.symmetry (docs/theory.md section 11): a 90 deg sector keeps a quarter of the particles
  // of the verification cylinder (3792); unsupported settings are input errors with a pointer.
  const std::string cylinder =
      std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/spinning_compressed_cylinder.json";
  const Result sector = run({"check", cylinder, "--set", "numerics.symmetry.sector.angle=90 deg"});
  ASSERT_EQ(sector.code, 0) << describe(sector);
  EXPECT_TRUE(contains(sector.out, "is valid: 948 particles")) << sector.out;
  EXPECT_TRUE(contains(sector.out, "symmetry: the particles of 1/4 of the scene")) << sector.out;
  const Result angle = run({"check", cylinder, "--set", "numerics.symmetry.sector.angle=70 deg"});
  EXPECT_EQ(angle.code, 2) << describe(angle);
  EXPECT_TRUE(contains(angle.err, "/numerics/symmetry: the sector angle must be 360 deg / N")) << angle.err;
  const Result axial = run({"check", cylinder, "--set", "numerics.symmetry.sector.angle=90 deg", "--set",
                            R"(numerics.symmetry.mirror_planes=[{"normal": [1, 0, 0]}])"});
  EXPECT_EQ(axial.code, 2) << describe(axial);
  EXPECT_TRUE(contains(axial.err, "mirror planes must be normal to the sector's axis")) << axial.err;
  const Result empty = run({"check", cylinder, "--set",
                            R"(numerics.symmetry.mirror_planes=[{"point": [0, 0, 1], "normal": [0, 0, 1]}])"});
  EXPECT_EQ(empty.code, 2) << describe(empty);
  EXPECT_TRUE(contains(empty.err, "has no particle inside the symmetry region")) << empty.err;
}

TEST_F(Cli, CheckStatesTheThermalStepping) {
  // The friction-extrusion quick case runs the sub-cycled thermal step (docs/theory.md eq. 26b) at time
  // step factor 0.05; switched off, check reports the every-step pass and its factor.
  const std::string fe = std::string(SPHFORGE_SOURCE_DIR) + "/cases/friction_extrusion/aa7075_pid_300kN_quick.json";
  const Result sub = run({"check", fe});
  ASSERT_EQ(sub.code, 0) << describe(sub);
  EXPECT_TRUE(contains(sub.out, "thermal step: sub-cycled (docs/theory.md eq. 26b)")) << sub.out;
  EXPECT_TRUE(contains(sub.out, "once per dt_thermal = 0.05 h^2")) << sub.out;
  const Result every =
      run({"check", fe, "--set", "thermal.subcycling=false", "--set", "thermal.time_step_factor=0.1"});
  ASSERT_EQ(every.code, 0) << describe(every);
  EXPECT_TRUE(contains(every.out, "thermal step: every step, which is at most dt_thermal = 0.1 h^2")) << every.out;
  EXPECT_FALSE(contains(every.out, "sub-cycled")) << every.out;
  EXPECT_TRUE(fs::is_empty(work())) << "check must not write anything";
}

TEST_F(Cli, CheckListsPassesAndFieldsWithoutWriting) {
  const Result r = run({"check", kQuickCase});
  ASSERT_EQ(r.code, 0) << describe(r);
  EXPECT_TRUE(contains(r.out, "case 'paste_orifice_quick' is valid")) << r.out;
  EXPECT_TRUE(contains(r.out, "passes:")) << r.out;
  for (const char* pass : {"neighbour_search", "continuity", "material:elastoplastic", "momentum", "contact", "integrate"})
    EXPECT_TRUE(contains(r.out, std::string("  ") + pass + "\n")) << pass << " not listed in\n" << r.out;
  std::string fields_line;
  for (const auto& line : lines_of(r.out))
    if (line.rfind("fields allocated:", 0) == 0) fields_line = line + " ";
  ASSERT_FALSE(fields_line.empty()) << r.out;
  for (const char* f : {" position ", " velocity ", " pressure ", " deviatoric_stress ", " density ", " plastic_strain "})
    EXPECT_TRUE(contains(fields_line, f)) << f << " not in " << fields_line;
  EXPECT_FALSE(contains(r.out, "temperature")) << r.out;
  EXPECT_FALSE(contains(r.out, "thermal step")) << "an isothermal case has no thermal step\n" << r.out;
  EXPECT_TRUE(fs::is_empty(work())) << "check must not write anything";

  // With overrides, the scene it reports is the overridden one: 4 layers x 448 columns.
  const Result tiny = run(concat({"check", kQuickCase}, kTinyCase));
  ASSERT_EQ(tiny.code, 0) << describe(tiny);
  EXPECT_TRUE(contains(tiny.out, "1792 particles, 3 tools")) << tiny.out;

  // And an invalid case is refused the same way as by run.
  const Result bad = run({"check", kQuickCase, "--set", "material.poisson_ratio=0.7"});
  expect_input_error(bad, kQuickCase, "/material/poisson_ratio", {"0.7"});
}

TEST_F(Cli, PluginsJsonListsTheFourPlugins) {
  const Result r = run({"plugins", "--json"});
  ASSERT_EQ(r.code, 0) << describe(r);
  EXPECT_FALSE(contains(r.err, "warning")) << r.err;
  json list;
  ASSERT_NO_THROW(list = json::parse(r.out)) << r.out;
  ASSERT_TRUE(list.is_array());
  std::map<std::string, json> by_name;
  for (const auto& p : list) {
    ASSERT_TRUE(p.contains("name") && p["name"].is_string()) << p.dump();
    by_name[p["name"].get<std::string>()] = p;
  }
  const std::map<std::string, std::string> expected = {
      {"elastoplastic", "material"}, {"coulomb", "contact"}, {"ram_extrusion", "process"}, {"prescribed", "controller"}};
  for (const auto& [name, kind] : expected) {
    SCOPED_TRACE(name);
    ASSERT_EQ(by_name.count(name), 1u) << r.out;
    const json& p = by_name[name];
    EXPECT_EQ(p.value("kind", ""), kind);
    EXPECT_FALSE(p.value("version", "").empty());
    EXPECT_FALSE(p.value("doc", "").empty());
    ASSERT_TRUE(p.contains("parameters") && p["parameters"].is_array()) << p.dump(2);
    EXPECT_FALSE(p["parameters"].empty());
    for (const auto& param : p["parameters"]) {
      EXPECT_TRUE(param.contains("name") && param["name"].is_string()) << param.dump();
      EXPECT_TRUE(param.contains("doc") && param["doc"].is_string() && !param["doc"].get<std::string>().empty())
          << param.dump();
      EXPECT_TRUE(param.contains("unit")) << "parameter without a unit entry: " << param.dump();
      if (param.contains("unit")) EXPECT_TRUE(param["unit"].is_string() || param["unit"].is_null()) << param.dump();
      if (param.value("type", "") == "number")
        EXPECT_FALSE(param.value("unit", "").empty()) << param.dump();
    }
  }
  // Spot checks of declared units.
  auto unit_of = [&](const std::string& plugin, const std::string& param) -> std::string {
    for (const auto& q : by_name[plugin]["parameters"])
      if (q.value("name", "") == param) return q.value("unit", "?");
    return "<absent>";
  };
  EXPECT_EQ(unit_of("elastoplastic", "yield_stress"), "Pa");
  EXPECT_EQ(unit_of("elastoplastic", "density"), "kg/m^3");
  EXPECT_EQ(unit_of("ram_extrusion", "billet_height"), "m");
  EXPECT_EQ(unit_of("coulomb", "friction_coefficient"), "1");

  const Result text = run({"plugins"});
  EXPECT_EQ(text.code, 0) << describe(text);
  for (const char* line : {"material elastoplastic ", "contact coulomb ", "process ram_extrusion ",
                           "controller prescribed "})
    EXPECT_TRUE(contains(text.out, line)) << line << " not in\n" << text.out;
  EXPECT_TRUE(contains(text.out, "yield_stress [Pa]")) << text.out;
}

TEST_F(Cli, HelpAndVersion) {
  const Result help = run({"--help"});
  EXPECT_EQ(help.code, 0) << describe(help);
  EXPECT_TRUE(contains(help.out, "sphforge run")) << help.out;
  const Result version = run({"--version"});
  EXPECT_EQ(version.code, 0) << describe(version);
  EXPECT_EQ(version.out.rfind("sphforge ", 0), 0u) << version.out;
}

// --- --out and --force ---------------------------------------------------------------------------

TEST_F(Cli, ExistingOutputFolderNeedsForceAndNothingIsDeleted) {
  const fs::path out = root() / "out";
  fs::create_directories(out);
  const std::string precious = "results of an earlier study\n";
  std::ofstream(out / "keep.txt") << precious;

  const Result refused = run(concat({"run", kQuickCase, "--set", "run.max_steps=3", "--quiet", "--out", out.string()},
                                    kTinyCase));
  EXPECT_EQ(refused.code, 2) << describe(refused);
  const auto lines = lines_of(refused.err);
  ASSERT_EQ(lines.size(), 1u) << describe(refused);
  EXPECT_EQ(lines[0].rfind("error: " + out.string(), 0), 0u) << lines[0];
  EXPECT_TRUE(contains(lines[0], "--force")) << lines[0];
  EXPECT_EQ(slurp(out / "keep.txt"), precious);
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator{}), 1) << "nothing may be written";

  const Result forced = run(concat(
      {"run", kQuickCase, "--set", "run.max_steps=3", "--quiet", "--force", "--out", out.string()}, kTinyCase));
  ASSERT_EQ(forced.code, 0) << describe(forced);
  EXPECT_EQ(slurp(out / "keep.txt"), precious) << "--force must not touch unrelated files";
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_EQ(read_json(out / "summary.json").value("steps", -1), 3);

  // A second forced run overwrites sphforge's own files, still keeping the unrelated one.
  const Result again = run(concat(
      {"run", kQuickCase, "--set", "run.max_steps=5", "--quiet", "--force", "--out", out.string()}, kTinyCase));
  ASSERT_EQ(again.code, 0) << describe(again);
  EXPECT_EQ(read_json(out / "summary.json").value("steps", -1), 5);
  EXPECT_EQ(slurp(out / "keep.txt"), precious);
}

TEST_F(Cli, OutNamingAFileIsRefused) {
  const fs::path file = root() / "a_file";
  std::ofstream(file) << "x";
  const Result r = run(concat({"run", kQuickCase, "--set", "run.max_steps=2", "--quiet", "--force", "--out",
                               file.string()},
                              kTinyCase));
  EXPECT_EQ(r.code, 2) << describe(r);
  EXPECT_TRUE(contains(r.err, "names a file")) << r.err;
  EXPECT_EQ(slurp(file), "x");
}

TEST_F(Cli, DefaultOutputFolderNeverReusesAnEarlierRun) {
  const auto args = concat({"run", kQuickCase, "--set", "run.max_steps=2", "--quiet"}, kTinyCase);
  const Result first = run(args);
  ASSERT_EQ(first.code, 0) << describe(first);
  const Result second = run(args);
  ASSERT_EQ(second.code, 0) << describe(second);
  EXPECT_TRUE(fs::exists(work() / "runs" / "paste_orifice_quick" / "summary.json"));
  EXPECT_TRUE(fs::exists(work() / "runs" / "paste_orifice_quick-2" / "summary.json"));
}

// A thermal body attached to a tool (docs/contact.md "Heat into the tools"): a tool name that does
// not exist, or a mechanical body, is an input error at the body's attached_to.
TEST_F(CliInput, AttachedBodyNeedsAnExistingToolAndNoMechanics) {
  const std::string source = std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/tool_heat_rotating_die.json";
  const fs::path unknown = root() / "unknown_tool.json", mechanical = root() / "mechanical.json";
  json doc = read_json(source);
  doc["process"]["bodies"][1]["attached_to"] = "nosuch";
  std::ofstream(unknown) << doc.dump(2) << "\n";
  expect_input_error(run({"check", unknown.string()}), unknown.string(), "/process/bodies/1/attached_to",
                     {"no tool or plane named 'nosuch'", "die"});
  doc = read_json(source);
  doc["process"]["bodies"][1]["mechanics"] = true;
  std::ofstream(mechanical) << doc.dump(2) << "\n";
  expect_input_error(run({"check", mechanical.string()}), mechanical.string(), "/process/bodies/1/attached_to",
                     {"thermal-only"});
}
