// numerics.thermal_neighbour_skin (docs/theory.md section 7): the thermal lists' own Verlet skin. Pairs in
// the skin contribute exact zeros, so a thicker skin changes only the order of the heat sums. The
// friction-drilling quick case (drill body turning at 100 x 5800 rpm, so the thermal lists are rebuilt
// nearly every step with the default skin) runs 0.3 s of process time, through the drill's first contact
// with the sheet (0.2 s), with the default skin (0.1 h) and with 0.6 h. Every history row's temperatures and
// drill heat must agree to 1e-10 relative: round-off of reordered sums (~1e-16 per operation over some
// 10,000 steps) stays far below that, a missing neighbour would not. The case's sub-cycled thermal step
// (eq. 26b) is switched off here: the thermal pass, and with it the lists' skin check, then runs every
// step, which is the situation the skin is for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

TEST(ThermalSkin, ThickerSkinGivesTheSameHeatFlow) {
  const std::string case_file = "../friction_drilling/hx220_m4_quick.json";
  const RunResult a = run_case(case_file, "thermal_skin_default",
                               {"run.end_time=0.003 s", "numerics.thermal_neighbour_skin=-1",
                                "thermal.subcycling=false", "thermal.time_step_factor=0.1"});
  ASSERT_EQ(a.code, 0) << a.err;
  const RunResult b = run_case(case_file, "thermal_skin_thick",
                               {"run.end_time=0.003 s", "numerics.thermal_neighbour_skin=0.6",
                                "thermal.subcycling=false", "thermal.time_step_factor=0.1"});
  ASSERT_EQ(b.code, 0) << b.err;
  const History ha = read_history(a.out / "history.csv"), hb = read_history(b.out / "history.csv");
  ASSERT_EQ(ha.rows, hb.rows);
  double worst = 0.0;
  for (const char* column : {"temperature_max_K", "temperature_mean_K", "probe_temperature_K", "drill_heat_to_tool_J"}) {
    const auto& x = ha[column];
    const auto& y = hb[column];
    for (std::size_t k = 0; k < ha.rows; ++k)
      worst = std::max(worst, std::abs(x[k] - y[k]) / std::max(std::abs(x[k]), 1e-300));
  }
  // The drill did touch the sheet: heat went into it.
  EXPECT_GT(ha["drill_heat_to_tool_J"].back(), 0.0);
  EXPECT_GT(ha["temperature_max_K"].back(), 300.0);
  char line[160];
  std::snprintf(line, sizeof line, "thermal skin 0.6 h against 0.1 h: largest relative difference %.3e\n", worst);
  std::printf("%s", line);
  record("verification_results.txt", line);
  EXPECT_LT(worst, 1e-10) << line;
}

}  // namespace
