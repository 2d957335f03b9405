// The friction_extrusion process end to end (docs/processes/friction_extrusion.md): its user errors
// are input errors (exit code 2, file and JSON pointer), and its friction heat rate (docs/theory.md
// eq. 104, recomputed from the particles' contact forces) agrees with the core's per-tool friction
// heat (eq. 18e) divided by the time scaling. The steady-state checks of the bundled quick case are
// the CTest case.friction_extrusion.aa7075_pid_300kN_quick (tests/cases/fe_quick.cmake).
#include <gtest/gtest.h>

#include "command_line.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace sphforge_test;

namespace {

const std::string kQuick = std::string(SPHFORGE_SOURCE_DIR) + "/cases/friction_extrusion/aa7075_pid_300kN_quick.json";

/// Runs sphforge with `args` from a scratch folder; stdout and stderr captured to files there.
Result sphforge(const std::vector<std::string>& args, const fs::path& dir) {
  fs::create_directories(dir);
  std::string cmd = "cd " + shell_quote(dir.string()) +
                    " && env -u SPHFORGE_PLUGIN_PATH OMP_WAIT_POLICY=PASSIVE OMP_NUM_THREADS=1 timeout -k 10 300 " +
                    shell_quote(SPHFORGE_EXECUTABLE);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  cmd += " >" + shell_quote((dir / "stdout.txt").string()) + " 2>" + shell_quote((dir / "stderr.txt").string());
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = status == -1 ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(dir / "stdout.txt");
  r.err = slurp(dir / "stderr.txt");
  return r;
}

fs::path scratch(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("sphforge_fe_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(p);
  return p;
}

TEST(FrictionExtrusion, SectorWithThermalToolBodiesIsAnInputError) {
  // The core rejects thermal-only bodies with symmetry; the process says so at its own parameter.
  const Result r = sphforge({"check", kQuick, "--set", "process.sector_count=4"}, scratch("sector"));
  EXPECT_EQ(r.code, 2) << describe(r);
  EXPECT_TRUE(contains(r.err, "aa7075_pid_300kN_quick.json at /process/sector_count")) << r.err;
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
  const std::vector<std::string> lines = lines_of(slurp(dir / "out" / "history.csv"));
  ASSERT_GT(lines.size(), 10u);
  const std::vector<std::string> head = split(lines[0], ',');
  auto column = [&](const std::string& name) {
    for (std::size_t k = 0; k < head.size(); ++k)
      if (head[k] == name) return k;
    ADD_FAILURE() << "no column " << name;
    return std::size_t{0};
  };
  const std::size_t process = column("friction_heat_rate_W"), core = column("die_friction_heat_W");
  int compared = 0;
  double worst = 0.0;
  for (std::size_t row = 1; row < lines.size(); ++row) {
    const std::vector<std::string> v = split(lines[row], ',');
    if (v.size() != head.size()) continue;
    const double q_process = std::stod(v[process]), q_core = std::stod(v[core]);
    if (q_core <= 0.0) continue;
    worst = std::max(worst, std::abs(10.0 * q_process - q_core) / q_core);  // time_scaling 10 (eq. 104)
    ++compared;
  }
  EXPECT_GT(compared, 10);
  // The contact pass evaluates |f_t| |v_t| with the velocity at the start of the step, the process
  // with the velocity after it: they differ by dt a_t, measured at most 4.7e-4 relative over the
  // whole 3 s quick run; 1e-3 bounds that lag, while a wrong scaling (x f or / f) or a wrong
  // projection would be off by a factor.
  EXPECT_LT(worst, 1e-3) << compared << " rows";
}

}  // namespace
