// Verification 1 (docs/verification.md section 1): longitudinal elastic wave in a bar.
// cases/verification/wave_bar.json: nu = 0, so the bar speed sqrt(E/rho) and the constrained
// (1D strain) speed sqrt((K + 4G/3)/rho) coincide and a plane front is an exact solution of the
// bar with free lateral faces. The speed is measured as time of flight of the front's half level
// between two probes on the axis, at 4 and 8 particles across the 100 mm section.
//
// Tolerance: 2 % on the speed extrapolated to zero spacing (Richardson, order 1), and an observed
// order within [0.7, 1.3]. Why extrapolated: the raw speed is 12 % (4 across) and 6 % (8 across)
// low. The error comes from the free lateral faces: the momentum equation (theory eq. 7) uses the
// uncorrected kernel gradient, whose moment M_xx = -sum_j V_j x_ij,x dW/dx is below 1 within 2h of
// a free face, so those particles respond too softly; their share of the section is proportional
// to dx / width, hence first order in dx and a function of the particles across the section only
// (docs/verification.md gives the numbers, including 2 across). The extrapolation removes exactly
// that first-order term; what remains (dispersion, lattice moment of the interior, 0.3 %) must be
// within 2 %.
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

TEST(WaveBar, SpeedConvergesToSqrtEOverRhoWithinTwoPercent) {
  const Measured coarse = measure("25 mm"), fine = measure("12.5 mm");
  const double e_coarse = (coarse.speed - kSpeed) / kSpeed, e_fine = (fine.speed - kSpeed) / kSpeed;
  const double order = std::log2(std::abs(e_coarse) / std::abs(e_fine));
  const double extrapolated = 2.0 * fine.speed - coarse.speed;  // Richardson, order 1
  const double e_extrapolated = (extrapolated - kSpeed) / kSpeed;
  char line[400];
  std::snprintf(line, sizeof line,
                "wave_bar: analytic %.4f m/s; dx 25 mm (%lld particles): %.4f m/s, error %+.4f %%; dx 12.5 mm (%lld "
                "particles): %.4f m/s, error %+.4f %%; observed order %.3f; extrapolated %.4f m/s, error %+.4f %%\n",
                kSpeed, coarse.particles, coarse.speed, 100 * e_coarse, fine.particles, fine.speed, 100 * e_fine, order,
                extrapolated, 100 * e_extrapolated);
  std::printf("%s", line);
  record("verification_results.txt", line);
  EXPECT_LT(std::abs(e_extrapolated), 0.02) << line;
  EXPECT_GT(order, 0.7) << line;
  EXPECT_LT(order, 1.3) << line;
  EXPECT_LT(std::abs(e_fine), std::abs(e_coarse)) << line;
}

}  // namespace
