// Validation (label `validation`, not run in CI: about 85 minutes on one loaded core, 29 on two idle
// ones; 12,000 particles and 51,577 steps): the oscillating plate of cases/verification/oscillating_plate.json at
// H/10 (dx = 2 mm) with the second-order gradient correction (theory section 18), two periods.
// Target (issue 3, verification item 3): the period within 5 % of the Euler-Bernoulli value
// 0.27684 s. The 5 % is the issue's, not a tuned bound. Measured 2026-11-30: 0.2898 s, +4.67 %
// (one thread, ad53f7d); 2026-12-01 as this CTest on 3774517 (2 threads, 1709 s): 0.28837 s, +4.16 %
// (docs/verification.md section 3, with H/4 to H/8 and the first order for comparison).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

TEST(OscillatingPlateValidation, SecondOrderAtH10WithinFivePercent) {
  constexpr double kPeriod = 0.27684;  // s, Euler-Bernoulli (the case's description)
  const RunResult r = run_case("oscillating_plate.json", "plate_second_2mm",
                               {"process.particle_spacing=2 mm", "numerics.gradient_correction_order=second",
                                "run.end_time=0.62 s", "run.threads=2"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json summary = read_summary(r.out);
  const json& m = summary["metrics"];
  ASSERT_TRUE(m.contains("tip_displacement_y_period_s")) << "no oscillation period detected";
  const double period = m["tip_displacement_y_period_s"].get<double>();
  const double error = period / kPeriod - 1.0;
  char text[200];
  std::snprintf(text, sizeof text, "oscillating plate H/10, second order: period %.5f s, %+.2f %% against %.5f s\n",
                period, 100 * error, kPeriod);
  std::printf("%s", text);
  record("validation_results.txt", text);
  EXPECT_LT(std::abs(error), 0.05) << text;
}

}  // namespace
