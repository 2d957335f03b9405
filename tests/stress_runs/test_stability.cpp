// Stress test (label `stress`, docs/stability.md): the oscillating plate (coarse, 0.02 s) at the
// default Courant number 0.3 completes, and at cfl 2.0 the instability detector stops it with exit
// code 3 and a diagnosis naming step, time, particle and field. The full sweep over cfl and jitter
// is scripts/stability_sweep.sh (its table is docs/stability.md).
#include <gtest/gtest.h>

#include <regex>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

const std::vector<std::string> kShort = {"run.end_time=0.02 s", "run.output_interval=0.01 s",
                                         "process.particle_spacing=5 mm"};

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(Stability, DefaultCflCompletes) {
  const RunResult r = run_case("oscillating_plate.json", "stability_cfl0.3", with(kShort, {"numerics.cfl=0.3"}));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_summary(r.out)["status"].get<std::string>(), "completed");
}

TEST(Stability, Cfl2IsDetectedWithDiagnosis) {
  const RunResult r = run_case("oscillating_plate.json", "stability_cfl2", with(kShort, {"numerics.cfl=2.0"}));
  ASSERT_EQ(r.code, 3) << r.err;
  const std::regex located(R"(numerical instability at step (\d+), t = ([0-9.eE+-]+) s, particle (\d+), field '(\w+)')");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.err, m, located)) << r.err;
  EXPECT_GT(std::stoll(m[1]), 0);
  const json summary = read_summary(r.out);
  EXPECT_EQ(summary["status"].get<std::string>(), "unstable");
  EXPECT_LT(std::stoll(m[3]), summary["particles"].get<long long>());
}

}  // namespace
