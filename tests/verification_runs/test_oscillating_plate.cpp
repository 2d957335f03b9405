// Verification 3 of the SPH-core issue (docs/verification.md, "Oscillating plate"): the clamped
// beam of Gray, Monaghan & Swift (2001), cases/verification/oscillating_plate.json, released with
// its first-mode velocity shape. Reference: the Euler-Bernoulli period of the 3D beam of square
// section, T = 2 pi L^2 / (1.8751^2 sqrt(E H^2 / (12 rho))) = 0.27684 s (Timoshenko's shear and
// rotary-inertia correction at L/H = 10 is +0.6 %).
//
// What this test asserts, and what it does not: the issue asks for the period within 5 % of the
// Euler-Bernoulli value. Measured (docs/bench/oscillating_plate/bench.csv): +34.3 % at 4 particles
// through the thickness, +16.6 % at 6, +10.6 % at 8 (observed orders 1.8 and 1.6); 5 % would need
// about 12-16 particles through the thickness, 10-30 min of CPU, too long for CI (this test runs
// its two resolutions on 2 threads, RUN_SERIAL, about 100 s). The test
// therefore asserts the convergence it can afford to show (4 and 6 particles through the thickness):
// the error falls with an observed order of at least 1 and the oscillation is clean (a period is
// detected, the amplitude stays within 20 % of v0 / omega measured). It does NOT claim 5 %.
// The same test runs H/4 with the second-order gradient correction (numerics.gradient_correction_order
// = "second", docs/theory.md section 18) against the first order at the same spacing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

constexpr double kPeriod = 0.27684;  // s, Euler-Bernoulli

double period_at(const std::string& spacing, const std::string& order = "first") {
  const RunResult r = run_case("oscillating_plate.json", "plate_" + order + "_" + spacing.substr(0, spacing.find(' ')),
                               {"process.particle_spacing=" + spacing, "run.end_time=0.8 s", "run.threads=2",
                                "numerics.gradient_correction_order=" + order});
  EXPECT_EQ(r.code, 0) << r.err;
  const json summary = read_summary(r.out);
  const json& m = summary["metrics"];
  EXPECT_TRUE(m.contains("tip_displacement_y_period_s")) << "no oscillation period detected";
  if (!m.contains("tip_displacement_y_period_s")) return 0.0;
  const double period = m["tip_displacement_y_period_s"].get<double>();
  // Amplitude against v0 / omega with the measured omega: a clean single-mode oscillation.
  const double omega = 2.0 * 3.14159265358979 / period, expected = 0.05 / omega;
  EXPECT_NEAR(m["tip_displacement_y_max_m"].get<double>(), expected, 0.2 * expected);
  return period;
}

// Both checks in one test because they share the first-order H/4 run (28 s of about 320 s on one
// thread); as two tests, ctest ran it twice.
//
// 1. Convergence: the first-order error falls from H/4 to H/6 with an observed order above 1.
// 2. The second-order gradient correction (docs/theory.md section 18) at H/4: the remedy for the
// surface strain error that the first-order correction makes at the outer fibres (0.80 of the exact
// bending strain on this lattice, tests/verification/test_second_order_gradient.cpp). Measured
// (docs/verification.md section 3): +10.5 % at H/4 against +34.0 % with the first order; the rest
// is the clamp's effective root about one spacing behind x = 0, the midpoint quadrature of the
// bending stiffness across 4 particles (+3.3 %), the artificial stress (+1.9 %) and Timoshenko
// (+0.6 %). Tolerance: the error must be at most half that of the first order at the same
// spacing. Why half: of the first order's +34 %, the surface strain error alone accounts for about
// +22 % (a stiffness of 0.67), so a remedy that works removes well over half of the
// error; a gradient that still evaluated the outer fibres' strain inside the beam would fail.
// Cost on one thread (2026-12-01): H/4 first order 28 s, H/4 second order 142 s (5x per step), H/6
// first order about 150 s.
TEST(OscillatingPlate, PeriodConvergesAndSecondOrderGradientHalvesTheErrorAtH4) {
  const double coarse = period_at("5 mm"), fine = period_at("3.3333333 mm");
  const double e_coarse = (coarse - kPeriod) / kPeriod, e_fine = (fine - kPeriod) / kPeriod;
  const double order = std::log(std::abs(e_coarse) / std::abs(e_fine)) / std::log(1.5);
  char line[300];
  std::snprintf(line, sizeof line,
                "oscillating_plate: Euler-Bernoulli %.5f s; H/4: %.5f s (%+.2f %%); H/6: %.5f s (%+.2f %%); observed "
                "order %.2f\n",
                kPeriod, coarse, 100 * e_coarse, fine, 100 * e_fine, order);
  std::printf("%s", line);
  record("verification_results.txt", line);
  EXPECT_LT(std::abs(e_fine), std::abs(e_coarse)) << line;
  EXPECT_GT(order, 1.0) << line;

  const double second = period_at("5 mm", "second");
  const double e_second = (second - kPeriod) / kPeriod;
  std::snprintf(line, sizeof line,
                "oscillating_plate H/4: first-order gradient %.5f s (%+.2f %%), second-order %.5f s (%+.2f %%)\n",
                coarse, 100 * e_coarse, second, 100 * e_second);
  std::printf("%s", line);
  record("verification_results.txt", line);
  EXPECT_LT(std::abs(e_second), 0.5 * std::abs(e_coarse)) << line;
}

}  // namespace
