// Verification of heat conduction (docs/theory.md eqs. 20-23) against analytic answers, on the
// bundled cases in cases/verification/ (thermal-only particles, so no mechanics pass runs).
// Each tolerance is stated with its reason; docs/verification.md holds the measured numbers.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "in_process_case.hpp"
#include "sphforge/case_file.hpp"

namespace {

using namespace sphforge;
namespace fs = std::filesystem;

using sphforge_test::InProcessCase;

InProcessCase run_case(const std::string& file, const std::vector<std::string>& overrides, const std::string& tag) {
  InProcessCase r = sphforge_test::make_case(file, overrides, tag);
  const auto result = r.sim->run(r.out, ProgressMode::Quiet);
  EXPECT_EQ(result.exit_code, 0) << result.message;
  return r;
}

/// Total heat content sum m_i c T_i (J) of a uniform-c scene, with physical masses.
double heat_content(const Simulation& sim, double c) {
  const double* m = sim.fields().f64(field::mass);
  const double* T = sim.fields().f64(field::temperature);
  double q = 0.0;
  for (std::size_t i = 0; i < sim.particle_count(); ++i) q += m[i] * c * T[i];
  return q;
}

/// Largest |T - T_exact| / dT on the centre line of the conduction_erf bar at spacing dx.
double erf_error(const std::string& dx, const std::string& tag, double* conservation = nullptr,
                 const std::vector<std::string>& extra = {}, double physical_time = 2.0) {
  std::vector<std::string> sets = {"process.particle_spacing=" + dx};
  sets.insert(sets.end(), extra.begin(), extra.end());
  const InProcessCase r = run_case("conduction_erf.json", sets, tag);
  const Simulation& sim = *r.sim;
  const double alpha = 50.0 / (8000.0 * 500.0), t = physical_time, T0 = 293.15, T1 = 393.15;
  const double* x = sim.fields().f64(field::position);
  const double* T = sim.fields().f64(field::temperature);
  double worst = 0.0;
  int samples = 0;
  for (std::size_t i = 0; i < sim.particle_count(); ++i) {
    // Centre line: 6 mm from the side faces, more than the kernel support (2.6 dx <= 3.9 mm).
    if (std::abs(x[3 * i + 1] - 6e-3) > 1.2e-3 || std::abs(x[3 * i + 2] - 6e-3) > 1.2e-3) continue;
    const double exact = 0.5 * (T0 + T1) - 0.5 * (T1 - T0) * std::erf(x[3 * i] / (2.0 * std::sqrt(alpha * t)));
    worst = std::max(worst, std::abs(T[i] - exact) / (T1 - T0));
    ++samples;
  }
  EXPECT_GT(samples, 50);
  if (conservation) {
    // Initial heat: half the bar at T1, half at T0 (equal particle counts by construction).
    const double c = 500.0;
    double m_total = 0.0;
    for (std::size_t i = 0; i < sim.particle_count(); ++i) m_total += sim.fields().f64(field::mass)[i];
    *conservation = std::abs(heat_content(sim, c) - m_total * c * 0.5 * (T0 + T1)) / (m_total * c * 0.5 * (T0 + T1));
  }
  return worst;
}

// Two bars at 120 degC and 20 degC put in contact; exact: T = 70 degC - 50 K erf(x / 2 sqrt(alpha t)).
// Particles jittered by 20 % of dx. Tolerance 2 % of the jump (the figure); measured 1.35 %
// at dx = 1 mm. The pair terms of eq. 20 are antisymmetric, so the heat content is conserved to
// round-off: 1e-12 relative (about 1e4 round-off errors of 1e-16 accumulated over the run).
TEST(HeatConduction, TransientErfSolutionOnJitteredParticles) {
  double conservation = 1.0;
  const double error = erf_error("1 mm", "erf", &conservation);
  std::printf("conduction_erf dx = 1 mm: max |T - T_exact| / dT = %.5f, heat content drift %.3e\n", error, conservation);
  EXPECT_LT(error, 0.02);
  EXPECT_LT(conservation, 1e-12);
}

// Time scaling (theory eq. 25): run 10x faster (end time 0.2 s, numerics.time_scaling = 10) the
// conduction must reach the state of 2 s of physical time: same tolerance as the unscaled run (2 %
// of the jump), since only the time axis is rescaled (the thermal step shrinks by the same factor).
TEST(HeatConduction, TimeScalingReachesThePhysicalState) {
  const double error = erf_error("1 mm", "erf_time_scaled", nullptr, {"numerics.time_scaling=10", "run.end_time=0.2 s"}, 2.0);
  std::printf("conduction_erf time_scaling 10, 0.2 s simulated: max |T - T_exact(2 s)| / dT = %.5f\n", error);
  EXPECT_LT(error, 0.02);
}

// Convergence of the erf problem with resolution: the error must fall as dx falls (observed order
// > 0.5; the measured order is about 0.7, limited by the first-order error of the initial jump on
// jittered particles). The three errors and orders are printed for docs/verification.md.
TEST(HeatConduction, ErfErrorConvergesWithResolution) {
  const std::vector<double> spacings = {2.0, 1.5, 1.0};  // mm
  std::vector<double> errors;
  for (double dx : spacings) {
    char text[32];
    std::snprintf(text, sizeof text, "%g mm", dx);
    errors.push_back(erf_error(text, "erf_conv"));
  }
  for (std::size_t k = 0; k < spacings.size(); ++k) {
    std::printf("conduction_erf dx = %.2f mm: error %.5f", spacings[k], errors[k]);
    if (k > 0)
      std::printf("  observed order %.2f", std::log(errors[k - 1] / errors[k]) / std::log(spacings[k - 1] / spacings[k]));
    std::printf("\n");
  }
  const double order = std::log(errors.front() / errors.back()) / std::log(spacings.front() / spacings.back());
  EXPECT_GT(order, 0.5);
  EXPECT_LT(errors.back(), errors.front());
}

// Steady conduction through two materials in series (k1 = 50, k2 = 10 W/(m K), 10 mm each, ends
// held at 100 and 0 degC). Each side's profile is fitted by a straight line through its interior
// centre-line particles and extrapolated to the interface x = 10 mm; the exact interface
// temperature is 83.33 degC. Tolerance 0.5 K (0.5 % of the 100 K drop): the profiles are linear, so
// the SPH Laplacian is exact inside each material and the harmonic-mean conductivity (eq. 21)
// carries the flux across the interface; what remains is the not-quite-steady state at t = 60 s
// (slowest decay time L^2 / (pi^2 alpha) of about 2 s) and the layers next to the held ends.
TEST(HeatConduction, TwoMaterialsInSeriesInterfaceTemperature) {
  const InProcessCase r = run_case("two_material_series.json", {}, "series");
  const Simulation& sim = *r.sim;
  const double* x = sim.fields().f64(field::position);
  const double* T = sim.fields().f64(field::temperature);
  // Least-squares line through (x, T) of the centre-line particles in [a, b].
  auto fit = [&](double a, double b, double at) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (std::size_t i = 0; i < sim.particle_count(); ++i) {
      if (std::abs(x[3 * i + 1] - 4e-3) > 0.6e-3 || std::abs(x[3 * i + 2] - 4e-3) > 0.6e-3) continue;
      if (x[3 * i] < a || x[3 * i] > b) continue;
      sx += x[3 * i];
      sy += T[i];
      sxx += x[3 * i] * x[3 * i];
      sxy += x[3 * i] * T[i];
      ++n;
    }
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    return (sy - slope * sx) / n + slope * at;
  };
  // Interior of each bar: two spacings away from the held ends and from the interface.
  const double hot_side = fit(3e-3, 8e-3, 10e-3) - 273.15, cold_side = fit(12e-3, 17e-3, 10e-3) - 273.15;
  const double exact = (50.0 * 100.0 / 0.01 + 10.0 * 0.0 / 0.01) / (50.0 / 0.01 + 10.0 / 0.01);
  std::printf("two_material_series: interface from the hot side %.4f degC, from the cold side %.4f degC, exact %.4f\n",
              hot_side, cold_side, exact);
  EXPECT_NEAR(hot_side, exact, 0.5);
  EXPECT_NEAR(cold_side, exact, 0.5);
}

// Newton cooling of a steel ball (Biot 0.032): the mass-weighted mean temperature against the
// lumped solution with the body's own volume V = N dx^3 and the area of the ball of that volume.
// Tolerance 5 % of the initial excess temperature: the Biot number itself makes the lumped answer
// about 1 % off, and the kernel area estimate (eq. 22) smooths the lattice's staircase surface.
TEST(HeatConduction, NewtonCoolingOfABallFollowsTheLumpedSolution) {
  const InProcessCase r = run_case("newton_cooling.json", {}, "newton");
  const Simulation& sim = *r.sim;
  const double dx = 1e-3, rho = 8000.0, c = 500.0, h = 600.0, T_inf = 293.15, T0 = 493.15;
  const double volume = static_cast<double>(sim.particle_count()) * dx * dx * dx;
  const double radius = std::cbrt(3.0 * volume / (4.0 * std::numbers::pi));
  const double tau = rho * c * volume / (h * 4.0 * std::numbers::pi * radius * radius);
  std::ifstream in(r.out / "history.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream hs(line);
    for (std::string name; std::getline(hs, name, ',');) header.push_back(name);
  }
  const auto col = std::find(header.begin(), header.end(), "temperature_mean_K") - header.begin();
  ASSERT_LT(static_cast<std::size_t>(col), header.size());
  double worst = 0.0, last_t = 0.0;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> row;
    for (std::string cell; std::getline(ls, cell, ',');) row.push_back(std::stod(cell));
    const double t = row[0], exact = T_inf + (T0 - T_inf) * std::exp(-t / tau);
    worst = std::max(worst, std::abs(row[static_cast<std::size_t>(col)] - exact) / (T0 - T_inf));
    last_t = t;
  }
  std::printf("newton_cooling: tau = %.3f s, worst |T_mean - T_lumped| / (T0 - T_inf) = %.4f over %.1f s\n", tau, worst,
              last_t);
  EXPECT_GT(last_t, tau);  // the comparison covers more than one time constant
  EXPECT_LT(worst, 0.05);
}

}  // namespace
