// Verification 1 (docs/verification.md section 1): longitudinal elastic wave in a bar.
// cases/verification/wave_bar.json: nu = 0, so the bar speed sqrt(E/rho) and the constrained
// (1D strain) speed sqrt((K + 4G/3)/rho) coincide and a plane front is an exact solution of the
// bar with free lateral faces. The speed is measured as time of flight of the front's half level
// between two probes on the axis, at 4 and 8 particles across the 100 mm section.
//
// Tolerance: 2 % on the raw speed at 4 and at 8 particles across the section (the figure).
// Measured: +0.002 % and -0.03 %. History: with the uncorrected kernel gradient in the momentum
// equation the speed was 12 % (4 across) and 6 % (8 across) low, because particles within 2h of the
// free lateral faces responded too softly; the variationally consistent corrected momentum
// equation (theory eq. 7) removed that error. The coarsest run (2 across) and the observed orders
// are printed and recorded; once the error reaches the resolution of the front timing (a few
// 1e-4) the order is noise and is not asserted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

constexpr double kE = 10e6, kRho = 1000.0, kPiston = 0.01;
const double kSpeed = std::sqrt(kE / kRho);  // nu = 0: E = K + 4G/3

struct Measured {
  double speed = 0.0;
  long long particles = 0;
};

Measured measure(const std::string& spacing, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> sets = {"process.particle_spacing=" + spacing, "material.youngs_modulus=10 MPa",
                                   "material.density=1000 kg/m^3", "material.poisson_ratio=0"};
  sets.insert(sets.end(), extra.begin(), extra.end());
  const RunResult r = run_case("wave_bar.json", "wave_bar_" + spacing.substr(0, spacing.find(' ')), sets);
  EXPECT_EQ(r.code, 0) << r.err;
  const History h = read_history(r.out / "history.csv");
  const json summary = read_summary(r.out);
  const json& m = summary["metrics"];
  const double x1 = m["near_velocity_x_x0_m"].get<double>(), x2 = m["far_velocity_x_x0_m"].get<double>();
  const double t1 = first_crossing(h["time_s"], h["near_velocity_x_m_s"], 0.5 * kPiston);
  const double t2 = first_crossing(h["time_s"], h["far_velocity_x_m_s"], 0.5 * kPiston);
  EXPECT_TRUE(std::isfinite(t1) && std::isfinite(t2)) << "the front did not reach both probes";
  return {(x2 - x1) / (t2 - t1), summary["particles"].get<long long>()};
}

TEST(WaveBar, SpeedWithinTwoPercentOfSqrtEOverRho) {
  const std::vector<std::string> spacings = {"50 mm", "25 mm", "12.5 mm"};
  std::vector<Measured> runs;
  std::vector<double> errors;
  for (const auto& dx : spacings) {
    runs.push_back(measure(dx));
    errors.push_back((runs.back().speed - kSpeed) / kSpeed);
  }
  std::string text = "wave_bar: analytic " + std::to_string(kSpeed) + " m/s;";
  for (std::size_t k = 0; k < spacings.size(); ++k) {
    char item[200];
    std::snprintf(item, sizeof item, " dx %s (%lld particles): %.4f m/s, error %+.4f %%", spacings[k].c_str(),
                  runs[k].particles, runs[k].speed, 100 * errors[k]);
    text += item;
    if (k > 0) {
      std::snprintf(item, sizeof item, ", observed order %.2f",
                    std::log2(std::abs(errors[k - 1]) / std::max(std::abs(errors[k]), 1e-300)));
      text += item;
    }
    text += ";";
  }
  text += "\n";
  std::printf("%s", text.c_str());
  record("verification_results.txt", text);
  EXPECT_LT(std::abs(errors[1]), 0.02) << text;
  EXPECT_LT(std::abs(errors[2]), 0.02) << text;
}

// Mass scaling (theory eq. 24): every particle's inertia times s = 4 must halve the wave speed,
// c / sqrt(s) = 50 m/s, while the stiffness (the material) is unchanged. Tolerance 2 %, as for the
// unscaled speed (the same discretisation; only the inertia changed).
TEST(WaveBar, MassScalingSlowsTheWaveBySqrtOfTheFactor) {
  const Measured scaled = measure("25 mm", {"numerics.mass_scaling=4", "run.end_time=0.02 s"});
  const double expected = kSpeed / 2.0, error = (scaled.speed - expected) / expected;
  std::printf("wave_bar mass_scaling 4: %.4f m/s against %.4f m/s, error %+.4f %%\n", scaled.speed, expected,
              100 * error);
  EXPECT_LT(std::abs(error), 0.02);
}

}  // namespace
