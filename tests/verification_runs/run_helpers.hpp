// Helpers of the verification runs: run the sphforge executable on a bundled case (with --set
// overrides, one OpenMP thread, passive waiting), read its history.csv, summary.json and the
// particle frames back.
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "command_line.hpp"

namespace sphforge_verification {

namespace fs = std::filesystem;
using nlohmann::json;
using sphforge_test::shell_quote;
using sphforge_test::slurp;

inline const std::string kExe = SPHFORGE_EXECUTABLE;
inline const fs::path kCases = fs::path(SPHFORGE_SOURCE_DIR) / "cases" / "verification";

struct RunResult {
  int code = -1;
  std::string err;
  fs::path out;
};

/// A fresh output folder under the test's working directory (the build tree).
inline fs::path output_dir(const std::string& name) {
  const fs::path dir = fs::current_path() / "verification_runs" / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir;
}

/// The environment a test's sphforge command runs in, as an `env ...` prefix: the build's own plugins,
/// OMP_WAIT_POLICY=PASSIVE, and one thread, or SPHFORGE_TEST_THREADS (a positive integer) for the
/// hour-long validation runs on a machine nothing else uses.
inline std::string sphforge_env() {
  std::string threads = "1";
  if (const char* env = std::getenv("SPHFORGE_TEST_THREADS"); env != nullptr && *env != '\0') {
    threads = env;
    if (threads.find_first_not_of("0123456789") != std::string::npos || std::stoi(threads) < 1)
      throw std::invalid_argument("SPHFORGE_TEST_THREADS='" + threads + "': not a positive integer");
  }
  return "env -u SPHFORGE_PLUGIN_PATH OMP_NUM_THREADS=" + threads + " OMP_WAIT_POLICY=PASSIVE ";
}

/// `sphforge run CASE --out OUT --force --quiet --set ...` in sphforge_env() (one thread by default):
/// the tests share a small machine. The particle updates do not depend on the thread count
/// (neighbour lists and per-particle sums are in a fixed order); sums over all particles are OpenMP
/// reductions and differ in their last digits (paste_orifice_quick on one and two
/// threads: the same steady pressure to all 17 digits, kinetic energy 3e-15 apart relative), so a
/// case whose controller reads such a sum (a PID on a tool force) can part at round-off level.
inline RunResult run_case(const std::string& case_file, const std::string& name, const std::vector<std::string>& sets) {
  RunResult r;
  r.out = output_dir(name);
  std::string line = sphforge_env() + shell_quote(kExe) + " run " + shell_quote((kCases / case_file).string()) +
                     " --out " + shell_quote(r.out.string()) + " --force --quiet";
  for (const std::string& s : sets) line += " --set " + shell_quote(s);
  const fs::path err = r.out.string() + ".stderr.txt";
  line += " >/dev/null 2>" + shell_quote(err.string());
  const int status = std::system(line.c_str());
  if (status != -1 && WIFEXITED(status)) r.code = WEXITSTATUS(status);
  r.err = slurp(err);
  return r;
}

/// history.csv as columns by name.
struct History {
  std::map<std::string, std::vector<double>> columns;
  std::size_t rows = 0;
  const std::vector<double>& operator[](const std::string& name) const {
    auto it = columns.find(name);
    if (it == columns.end()) throw std::runtime_error("history.csv has no column " + name);
    return it->second;
  }
};

inline History read_history(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream hs(line);
  for (std::string name; std::getline(hs, name, ',');) names.push_back(name);
  History h;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::size_t c = 0;
    for (std::string cell; std::getline(ls, cell, ',') && c < names.size(); ++c) h.columns[names[c]].push_back(std::stod(cell));
    ++h.rows;
  }
  return h;
}

inline json read_summary(const fs::path& dir) { return json::parse(slurp(dir / "summary.json")); }

/// One particle frame: point data arrays by name (all components, row-major) and the ids.
struct Frame {
  std::size_t count = 0;
  std::map<std::string, std::vector<double>> arrays;
  std::map<std::string, int> components;
};

inline Frame read_frame(const fs::path& vtu) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(vtu.string().c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  Frame f;
  if (!grid) return f;
  f.count = static_cast<std::size_t>(grid->GetNumberOfPoints());
  vtkPointData* pd = grid->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a) {
    vtkDataArray* arr = pd->GetArray(a);
    if (!arr || !arr->GetName()) continue;
    const int nc = arr->GetNumberOfComponents();
    std::vector<double> values(f.count * static_cast<std::size_t>(nc));
    for (vtkIdType i = 0; i < static_cast<vtkIdType>(f.count); ++i)
      for (int c = 0; c < nc; ++c) values[static_cast<std::size_t>(i) * nc + c] = arr->GetComponent(i, c);
    f.arrays[arr->GetName()] = std::move(values);
    f.components[arr->GetName()] = nc;
  }
  // The particle positions (the grid's points) as the array "position".
  std::vector<double> x(3 * f.count);
  for (vtkIdType i = 0; i < static_cast<vtkIdType>(f.count); ++i) grid->GetPoint(i, &x[3 * static_cast<std::size_t>(i)]);
  f.arrays["position"] = std::move(x);
  f.components["position"] = 3;
  return f;
}

/// The frames of a run in time order (particles_NNNNNN.vtu).
inline std::vector<fs::path> frames(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".vtu" && e.path().filename().string().rfind("particles_", 0) == 0) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

/// First time at which `values` reaches `level` from below, linearly interpolated; NaN if never.
inline double first_crossing(const std::vector<double>& t, const std::vector<double>& values, double level) {
  for (std::size_t k = 1; k < values.size(); ++k)
    if (values[k - 1] < level && values[k] >= level)
      return t[k - 1] + (t[k] - t[k - 1]) * (level - values[k - 1]) / (values[k] - values[k - 1]);
  return std::nan("");
}

/// Appends `text` to a file in the build tree (results a test reports, for docs/verification.md).
inline void record(const std::string& file, const std::string& text) {
  std::ofstream out(fs::current_path() / file, std::ios::app);
  out << text;
}

}  // namespace sphforge_verification
