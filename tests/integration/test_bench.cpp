// `sphforge bench` end to end on the bundled quick case, shrunk through --set (a 6 mm billet,
// 20 steps, spacings of 1.5 mm and 1 mm: under a second for the whole bench): bench.csv header and
// rows, the run folders, bench.png read back with VTK, errors against a reference file, and the
// exit codes and messages of invalid input, of an occupied --out and of runs that all blow up.
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
#include <regex>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkDataArray.h>

namespace fs = std::filesystem;
using nlohmann::json;
using namespace sphforge_test;

namespace {

const std::string kExe = SPHFORGE_EXECUTABLE;
const std::string kQuickCase = std::string(SPHFORGE_SOURCE_DIR) + "/cases/ram_extrusion/paste_orifice_quick.json";

// A billet of 6 mm (4 layers at the coarsest spacing, the process's minimum) and 20 steps.
const std::vector<std::string> kSmall = {"--set", "process.billet_height=6 mm", "--set", "run.max_steps=20",
                                         "--set", "material.density=1e7 kg/m^3"};
const std::string kTwoSpacings = "1.5 mm, 1e-3";

/// bench.csv as strings (an empty cell is an empty string) with the header.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int column(const std::string& name) const {
    auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
  double number(std::size_t row, const std::string& name) const {
    const int c = column(name);
    if (c < 0 || row >= rows.size() || rows[row][c].empty()) return std::nan("");
    return std::stod(rows[row][c]);
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
    csv.rows.push_back(split(lines[k], ','));
    EXPECT_EQ(csv.rows.back().size(), csv.header.size()) << file << " line " << k + 1 << ": " << lines[k];
  }
  return csv;
}

json read_json(const fs::path& file) {
  std::ifstream in(file);
  return json::parse(in);
}

class Bench : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("sphforge_bench_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "work");
    fs::create_directories(root_ / "capture");
  }
  void TearDown() override {
    std::error_code ec;
    if (!HasFailure()) fs::remove_all(root_, ec);
    else std::fprintf(stderr, "files of the failed test kept in %s\n", root_.c_str());
  }

  /// Runs sphforge in work() with stdout and stderr captured apart; OMP_WAIT_POLICY=PASSIVE and
  /// one thread keep the runs quick on a busy machine; a hard time limit guards against a hang.
  Result run(const std::vector<std::string>& args) {
    const fs::path out = root_ / "capture" / ("stdout_" + std::to_string(counter_) + ".txt");
    const fs::path err = root_ / "capture" / ("stderr_" + std::to_string(counter_) + ".txt");
    ++counter_;
    std::string cmd = "cd " + shell_quote(work().string()) +
                      " && env -u SPHFORGE_PLUGIN_PATH OMP_WAIT_POLICY=PASSIVE OMP_NUM_THREADS=1 timeout -k 10 120 " +
                      shell_quote(kExe);
    for (const auto& a : args) cmd += " " + shell_quote(a);
    cmd += " >" + shell_quote(out.string()) + " 2>" + shell_quote(err.string());
    const int status = std::system(cmd.c_str());
    Result r;
    if (status != -1 && WIFEXITED(status)) r.code = WEXITSTATUS(status);
    else if (status != -1 && WIFSIGNALED(status)) r.code = 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  fs::path work() const { return root_ / "work"; }
  fs::path root() const { return root_; }

  /// A bad invocation: exit 2, one line on stderr naming `where` and each needle, nothing written.
  void expect_input_error(const std::vector<std::string>& args, const std::string& where,
                          const std::vector<std::string>& needles) {
    const fs::path out = root() / "refused";
    const Result r = run(concat(concat({"bench"}, args), {"--out", out.string()}));
    EXPECT_EQ(r.code, 2) << describe(r);
    const auto lines = lines_of(r.err);
    ASSERT_EQ(lines.size(), 1u) << describe(r);
    EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
    EXPECT_TRUE(contains(lines[0], where)) << "expected '" << where << "' in: " << lines[0];
    for (const auto& n : needles) EXPECT_TRUE(contains(lines[0], n)) << "expected '" << n << "' in: " << lines[0];
    EXPECT_FALSE(fs::exists(out)) << "nothing may be written for invalid input";
    EXPECT_TRUE(fs::is_empty(work()));
  }

  fs::path root_;
  int counter_ = 0;
};

const std::vector<std::string> kRunColumns = {"spacing_m",            "particles_1", "steps_1",    "wall_s",
                                              "particle_steps_per_s", "peak_rss_MB", "exit_code_1"};

}  // namespace

TEST_F(Bench, TwoSpacingsWriteCsvPlotJsonAndRunFolders) {
  const fs::path out = root() / "bench";
  const Result r = run(concat({"bench", kQuickCase, "--spacing", kTwoSpacings, "--out", out.string()}, kSmall));
  ASSERT_EQ(r.code, 0) << describe(r);

  // bench.csv: the run columns, then each metric with its relative error; every name ends with a unit.
  const Csv csv = read_csv(out / "bench.csv");
  ASSERT_GE(csv.header.size(), kRunColumns.size() + 2);
  EXPECT_EQ(std::vector<std::string>(csv.header.begin(), csv.header.begin() + kRunColumns.size()), kRunColumns);
  EXPECT_EQ((csv.header.size() - kRunColumns.size()) % 2, 0u);
  for (std::size_t c = kRunColumns.size(); c + 1 < csv.header.size(); c += 2) {
    const std::string& value = csv.header[c];
    const std::string& error = csv.header[c + 1];
    EXPECT_TRUE(std::regex_match(error, std::regex(R"(\w+_error_1)"))) << error;
    // The error column is <metric>_error_1, the value column the metric (with _1 when unitless).
    const std::string metric = error.substr(0, error.size() - 8);
    EXPECT_TRUE(value == metric || value == metric + "_1") << value << " / " << error;
  }
  for (const auto& name : csv.header)
    EXPECT_TRUE(std::regex_search(name, std::regex(R"(_(m|1|s|MB|Pa|N|per_s)$)"))) << "column without a unit: " << name;
  for (const char* metric : {"peak_extrusion_pressure_Pa", "final_ram_displacement_m", "extruded_particles_1"})
    EXPECT_GE(csv.column(metric), 0) << metric;

  ASSERT_EQ(csv.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(csv.number(0, "spacing_m"), 1.5e-3);
  EXPECT_DOUBLE_EQ(csv.number(1, "spacing_m"), 1e-3);
  EXPECT_LT(csv.number(0, "particles_1"), csv.number(1, "particles_1")) << "finer spacing, more particles";
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(csv.number(i, "steps_1"), 20.0);
    EXPECT_EQ(csv.number(i, "exit_code_1"), 0.0);
    EXPECT_GT(csv.number(i, "wall_s"), 0.0);
    EXPECT_GT(csv.number(i, "particle_steps_per_s"), 0.0);
    EXPECT_GT(csv.number(i, "peak_rss_MB"), 1.0);
    EXPECT_LT(csv.number(i, "peak_rss_MB"), 4000.0);
    // Each run's own output, readable as a normal run's.
    const fs::path folder = out / "runs" / (i == 0 ? "dx_1.5mm" : "dx_1mm");
    ASSERT_TRUE(fs::exists(folder / "summary.json")) << folder;
    const json summary = read_json(folder / "summary.json");
    EXPECT_EQ(summary.value("particles", -1.0), csv.number(i, "particles_1"));
    EXPECT_DOUBLE_EQ(summary["metrics"]["peak_extrusion_pressure_Pa"].get<double>(),
                     csv.number(i, "peak_extrusion_pressure_Pa"));
    EXPECT_TRUE(fs::exists(folder / "particles.pvd"));
  }
  // Without --reference the finest run is the reference: its errors are 0, the coarser one's are
  // |value - finest| / |finest|.
  const double p0 = csv.number(0, "peak_extrusion_pressure_Pa"), p1 = csv.number(1, "peak_extrusion_pressure_Pa");
  ASSERT_GT(std::abs(p1), 0.0);
  EXPECT_EQ(csv.number(1, "peak_extrusion_pressure_Pa_error_1"), 0.0);
  EXPECT_NEAR(csv.number(0, "peak_extrusion_pressure_Pa_error_1"), std::abs(p0 - p1) / std::abs(p1), 1e-12);
  const json bench = read_json(out / "bench.json");
  EXPECT_EQ(bench["reference"].value("kind", ""), "finest_spacing");
  EXPECT_DOUBLE_EQ(bench["reference"].value("spacing_m", 0.0), 1e-3);
  EXPECT_EQ(bench.value("parameter", ""), "process.particle_spacing");

  // The table on stdout names both spacings; the error table names the reference.
  EXPECT_TRUE(contains(r.out, "1.5 mm") && contains(r.out, "1 mm")) << r.out;
  EXPECT_TRUE(contains(r.out, "finest")) << r.out;

  // bench.png: a valid PNG of the documented size, with the series' colour drawn in it.
  const std::string png = (out / "bench.png").string();
  vtkNew<vtkPNGReader> reader;
  ASSERT_TRUE(reader->CanReadFile(png.c_str())) << png;
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 1100);
  EXPECT_EQ(dims[1], 680);
  EXPECT_EQ(dims[2], 1);
  vtkDataArray* pixels = image->GetPointData()->GetScalars();
  ASSERT_NE(pixels, nullptr);
  ASSERT_GE(pixels->GetNumberOfComponents(), 3);
  const std::string hex = bench["plot"]["colours"].value("peak_extrusion_pressure_Pa", "");
  ASSERT_EQ(hex.size(), 7u) << bench["plot"].dump();
  const int rgb[3] = {std::stoi(hex.substr(1, 2), nullptr, 16), std::stoi(hex.substr(3, 2), nullptr, 16),
                      std::stoi(hex.substr(5, 2), nullptr, 16)};
  vtkIdType coloured = 0, white = 0;
  for (vtkIdType p = 0; p < pixels->GetNumberOfTuples(); ++p) {
    const double* t = pixels->GetTuple(p);
    if (t[0] == rgb[0] && t[1] == rgb[1] && t[2] == rgb[2]) ++coloured;
    if (t[0] == 255 && t[1] == 255 && t[2] == 255) ++white;
  }
  EXPECT_GT(coloured, 50) << "the pressure error's polyline and markers are drawn in " << hex;
  // The drawn metrics take the palette's 8 colours in turn and the others none (null), so up to 8
  // drawn metrics never share a colour however many are listed (colours by list index did: with 12
  // metrics of which 2 drawn, the 4th and the 12th looked the same).
  std::set<std::string> distinct;
  std::size_t drawn = 0, listed = 0;
  for (const auto& [metric, colour] : bench["plot"]["colours"].items()) {
    ++listed;
    bool positive = false;  // drawn iff some run has a positive error (bench.csv)
    for (std::size_t i = 0; i < csv.rows.size(); ++i) positive = positive || csv.number(i, metric + "_error_1") > 0.0;
    EXPECT_EQ(colour.is_null(), !positive) << metric;
    if (colour.is_null()) continue;
    ++drawn;
    distinct.insert(colour.get<std::string>());
  }
  std::printf("plot: %zu of %zu metrics drawn, %zu colours\n", drawn, listed, distinct.size());
  EXPECT_GE(drawn, 1u);
  EXPECT_EQ(distinct.size(), std::min<std::size_t>(drawn, 8));
  EXPECT_GT(white, pixels->GetNumberOfTuples() / 2) << "a white background";
}

TEST_F(Bench, ReferenceFileGivesFiniteErrors) {
  // One value as a plain number (in the metric's unit, Pa), one with a unit ("5 um" for a metric in m).
  const fs::path reference = root() / "reference.json";
  std::ofstream(reference) << R"({"source": "test", "metrics": {"peak_extrusion_pressure_Pa": 1.5e5,
                                  "final_ram_displacement_m": "5 um"}})";
  const fs::path out = root() / "bench";
  const Result r = run(concat({"bench", kQuickCase, "--spacing", kTwoSpacings, "--reference", reference.string(),
                               "--out", out.string(), "--parameter", "/process/particle_spacing"},
                              kSmall));
  ASSERT_EQ(r.code, 0) << describe(r);
  const Csv csv = read_csv(out / "bench.csv");
  ASSERT_EQ(csv.rows.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const double p = csv.number(i, "peak_extrusion_pressure_Pa");
    const double e = csv.number(i, "peak_extrusion_pressure_Pa_error_1");
    ASSERT_TRUE(std::isfinite(e)) << "row " << i;
    EXPECT_NEAR(e, std::abs(p - 1.5e5) / 1.5e5, 1e-12);
    const double d = csv.number(i, "final_ram_displacement_m");
    const double ed = csv.number(i, "final_ram_displacement_m_error_1");
    ASSERT_TRUE(std::isfinite(ed)) << "row " << i;
    EXPECT_NEAR(ed, std::abs(d - 5e-6) / 5e-6, 1e-9);
    EXPECT_GT(ed, 0.0);
    // A metric the reference does not name has no error.
    EXPECT_TRUE(std::isnan(csv.number(i, "steady_window_start_m_error_1")));
  }
  const json bench = read_json(out / "bench.json");
  EXPECT_EQ(bench["reference"].value("kind", ""), "file");
  EXPECT_DOUBLE_EQ(bench["reference"]["metrics"].value("final_ram_displacement_m", 0.0), 5e-6);
  EXPECT_TRUE(contains(r.out, reference.string())) << r.out;
}

TEST_F(Bench, BadSpacingListIsRefusedNamingTheOption) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"", "comma-separated"},  {"abc", "'abc'"},         {"1 kg", "'1 kg'"},
      {"1 mm,,0.5 mm", "empty"}, {"-1 mm", "positive"},   {"1 mm, 1e-3", "twice"}};
  for (const auto& [list, needle] : bad) {
    SCOPED_TRACE("--spacing '" + list + "'");
    expect_input_error(concat({kQuickCase, "--spacing", list}, kSmall), "--spacing", {needle});
  }
  expect_input_error(concat({kQuickCase}, kSmall), "--spacing", {"needs --spacing"});
}

TEST_F(Bench, BadCaseParameterOrReferenceIsRefusedNamingFileAndPointer) {
  const std::string missing_case = (root() / "no_such_case.json").string();
  expect_input_error({missing_case, "--spacing", kTwoSpacings}, missing_case, {"cannot open case file"});
  expect_input_error(concat({kQuickCase, "--spacing", kTwoSpacings, "--parameter", "process.no_such_key"}, kSmall),
                     "/process/no_such_key", {"unknown key"});
  expect_input_error(concat({kQuickCase, "--spacing", kTwoSpacings, "--parameter", "process..x"}, kSmall),
                     "--parameter", {"process..x"});

  const std::string no_reference = (root() / "no_such_reference.json").string();
  expect_input_error(concat({kQuickCase, "--spacing", kTwoSpacings, "--reference", no_reference}, kSmall),
                     no_reference, {"cannot open reference file"});
  const fs::path wrong_unit = root() / "wrong_unit.json";
  std::ofstream(wrong_unit) << R"({"metrics": {"final_ram_displacement_m": "2 kN"}})";
  expect_input_error(concat({kQuickCase, "--spacing", kTwoSpacings, "--reference", wrong_unit.string()}, kSmall),
                     wrong_unit.string() + " at /metrics/final_ram_displacement_m", {"2 kN"});
  const fs::path no_metrics = root() / "no_metrics.json";
  std::ofstream(no_metrics) << R"({"final_ram_displacement_m": 1})";
  expect_input_error(concat({kQuickCase, "--spacing", kTwoSpacings, "--reference", no_metrics.string()}, kSmall),
                     no_metrics.string() + " at /metrics", {"missing"});
  const fs::path not_json = root() / "not_json.json";
  std::ofstream(not_json) << "{\"metrics\": {\n  \"x\": }";
  expect_input_error(concat({kQuickCase, "--spacing", kTwoSpacings, "--reference", not_json.string()}, kSmall),
                     not_json.string(), {"JSON syntax error at line 2"});
  const fs::path not_a_number = root() / "not_a_number.json";
  std::ofstream(not_a_number) << R"({"metrics": {"a/b": [1]}})";
  expect_input_error(concat({kQuickCase, "--spacing", kTwoSpacings, "--reference", not_a_number.string()}, kSmall),
                     not_a_number.string() + " at /metrics/a~1b", {"expected a number"});
}

TEST_F(Bench, ExistingOutputFolderNeedsForceAndNothingIsDeleted) {
  const fs::path out = root() / "bench";
  fs::create_directories(out);
  const std::string precious = "results of an earlier study\n";
  std::ofstream(out / "keep.txt") << precious;

  const Result refused = run(concat({"bench", kQuickCase, "--spacing", kTwoSpacings, "--out", out.string()}, kSmall));
  EXPECT_EQ(refused.code, 2) << describe(refused);
  const auto lines = lines_of(refused.err);
  ASSERT_EQ(lines.size(), 1u) << describe(refused);
  EXPECT_EQ(lines[0].rfind("error: " + out.string(), 0), 0u) << lines[0];
  EXPECT_TRUE(contains(lines[0], "--force")) << lines[0];
  EXPECT_EQ(slurp(out / "keep.txt"), precious);
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator{}), 1) << "nothing may be written";

  const Result forced =
      run(concat({"bench", kQuickCase, "--spacing", kTwoSpacings, "--out", out.string(), "--force"}, kSmall));
  ASSERT_EQ(forced.code, 0) << describe(forced);
  EXPECT_EQ(slurp(out / "keep.txt"), precious) << "--force must not touch unrelated files";
  EXPECT_EQ(read_csv(out / "bench.csv").rows.size(), 2u);
}

TEST_F(Bench, EveryRunUnstableExitsThreeAndRecordsIt) {
  // The settings of the CLI's instability test (cfl = 2, soft contact, no artificial viscosity).
  const fs::path out = root() / "bench";
  const Result r = run(concat({"bench", kQuickCase, "--spacing", kTwoSpacings, "--out", out.string(), "--set",
                               "numerics.cfl=2", "--set", "contact.stiffness_factor=0.001", "--set",
                               R"(numerics.artificial_viscosity={"alpha":0,"beta":0})", "--set", "run.max_steps=300"},
                              concat({"--set", "process.billet_height=6 mm"}, {"--set", "material.density=1e7 kg/m^3"})));
  EXPECT_EQ(r.code, 3) << describe(r);
  const Csv csv = read_csv(out / "bench.csv");
  ASSERT_EQ(csv.rows.size(), 2u) << "the bench goes on after an unstable run";
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(csv.number(i, "exit_code_1"), 3.0);
    EXPECT_GT(csv.number(i, "steps_1"), 0.0);
    EXPECT_LT(csv.number(i, "steps_1"), 300.0);
  }
  EXPECT_TRUE(contains(r.out, "unstable")) << r.out;
  EXPECT_TRUE(contains(r.out, "numerical instability at step")) << r.out;
  const json bench = read_json(out / "bench.json");
  ASSERT_EQ(bench["runs"].size(), 2u);
  EXPECT_EQ(bench["runs"][0].value("status", ""), "unstable");
  EXPECT_TRUE(fs::exists(out / "bench.png"));
}

TEST_F(Bench, HelpDescribesBench) {
  const Result r = run({"--help"});
  ASSERT_EQ(r.code, 0) << describe(r);
  for (const char* needle : {"sphforge bench", "--spacing", "--reference", "finest", "bench.csv", "docs/bench.md"})
    EXPECT_TRUE(contains(r.out, needle)) << needle;
  const Result misplaced = run({"run", kQuickCase, "--spacing", "1 mm"});
  EXPECT_EQ(misplaced.code, 2) << describe(misplaced);
  EXPECT_TRUE(contains(misplaced.err, "--spacing is an option of bench")) << describe(misplaced);
}

TEST_F(Bench, DefaultCaseAndOutputFolderNeverReuseAnEarlierBench) {
  // Without CASE the bundled quick case runs; without --out the bench goes to runs/<case>-bench,
  // then runs/<case>-bench-2 rather than touching the first.
  const auto args = concat({"bench", "--spacing", kTwoSpacings, "--quiet"}, kSmall);
  const Result first = run(args);
  ASSERT_EQ(first.code, 0) << describe(first);
  EXPECT_TRUE(first.out.empty()) << "--quiet: no table\n" << first.out;
  const Result second = run(args);
  ASSERT_EQ(second.code, 0) << describe(second);
  for (const char* folder : {"paste_orifice_quick-bench", "paste_orifice_quick-bench-2"}) {
    const fs::path dir = work() / "runs" / folder;
    EXPECT_EQ(read_csv(dir / "bench.csv").rows.size(), 2u) << dir;
    EXPECT_TRUE(fs::exists(dir / "bench.png")) << dir;
    EXPECT_TRUE(fs::exists(dir / "runs" / "dx_1mm" / "summary.json")) << dir;
  }
}
