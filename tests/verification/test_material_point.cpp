// Verification of the material plugins at a single material point (no SPH): the plugins are
// loaded as in a run and driven with a prescribed velocity gradient L, step by step, as the core
// drives them (docs/theory.md section 5, eqs. 15-17 and 33-38; docs/verification.md section 9).
// The driver integrates the strain exactly (constant L per step) and supplies the density and
// temperature; the material returns stress, pressure, plastic strain and plastic heat.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "sphforge/errors.hpp"
#include "sphforge/fields.hpp"
#include "sphforge/parameters.hpp"
#include "sphforge/plugin_loader.hpp"

namespace {

using namespace sphforge;

PluginLoader& loader() {
  static PluginLoader l({SPHFORGE_PLUGIN_BUILD_DIR});
  return l;
}

std::unique_ptr<Material> make(const std::string& plugin, const json& params) {
  const LoadedPlugin& lp = loader().load(PluginKind::Material, plugin);
  const ParamValues v = validate_parameters(params, lp.descriptor->parameters, "material_point.json", "/material");
  return lp.descriptor->make_material(v);
}

/// One material point: the fields the material declares, and the batch arrays the core owns.
struct Point {
  std::unique_ptr<Material> material;
  FieldRegistry fields;
  double L[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  double S[6] = {0, 0, 0, 0, 0, 0};
  double pressure = 0.0, density = 0.0, temperature = 0.0, heat = 0.0;

  Point(const std::string& plugin, const json& params) : material(make(plugin, params)) {
    for (const FieldInfo& f : material->fields()) fields.declare(f, "material");
    fields.allocate(1);
    material->initialize(fields, 0, 1);
    density = material->reference_density();
  }
  /// One step of length dt with the velocity gradient L; `thermal`: pass temperature and heat source.
  void step(double dt, bool thermal = false) {
    MaterialBatch b;
    b.count = 1;
    b.dt = dt;
    b.velocity_gradient = L;
    b.density = &density;
    b.deviatoric_stress = S;
    b.pressure = &pressure;
    b.fields = &fields;
    heat = 0.0;
    if (thermal) {
      b.temperature = &temperature;
      b.heat_source = &heat;
    }
    material->update_stress(b);
  }
  double eps_p() const { return fields.f64(field::plastic_strain)[0]; }
  double yield() const { return fields.f64("yield_stress")[0]; }
  double von_mises() const {
    const double ss = S[0] * S[0] + S[1] * S[1] + S[2] * S[2] + 2.0 * (S[3] * S[3] + S[4] * S[4] + S[5] * S[5]);
    return std::sqrt(1.5 * ss);
  }
};

void record(const std::string& line) {
  std::printf("%s\n", line.c_str());
  std::FILE* f = std::fopen("verification_results.txt", "a");
  if (f) {
    std::fprintf(f, "%s\n", line.c_str());
    std::fclose(f);
  }
}

constexpr double kE = 200e9, kNu = 0.3, kRho = 7800.0, kY0 = 300e6;

/// The same linear-hardening J2 law from both plugins: elastoplastic (yield_stress, H) and
/// johnson_cook with n = 1, C = 0, isothermal (sigma_y = A + B eps_p, eq. 36).
json law_params(const std::string& plugin, double H) {
  if (plugin == "elastoplastic")
    return {{"density", kRho}, {"youngs_modulus", kE}, {"poisson_ratio", kNu}, {"yield_stress", kY0},
            {"hardening_modulus", H}, {"output_fields", json::array({"yield_stress"})}};
  return {{"density", kRho}, {"youngs_modulus", kE}, {"poisson_ratio", kNu}, {"A", kY0}, {"B", H}, {"n", 1.0},
          {"reference_temperature", 293.15}, {"melting_temperature", 1800.0}, {"output_fields", json::array({"yield_stress"})}};
}

struct PathCase {
  std::string plugin;
  double H;
};

class J2Paths : public ::testing::TestWithParam<PathCase> {};

// Uniaxial stress: axial strain eps_a with the lateral strain eps_l of the closed-form answer,
// eps_l = -nu eps_a elastically and d eps_l = -(nu H/E + 1/2)/(1 + H/E) d eps_a in plastic flow; the
// deviatoric direction diag(2, -1, -1)/3 never changes, so the radial return is exact for linear
// hardening at any step size. The driver gives the density rho0 (1 - eps_v) so that the linear
// equation of state (eq. 17) returns p = -K eps_v, the small-strain volumetric law the closed form
// assumes. Answer: sigma_xx = E eps_a up to sigma_y0, then sigma_y0 + H eps_p with
// eps_p = (eps_a - sigma_y0/E)/(1 + H/E); sigma_yy = sigma_zz = 0.
// Tolerance 1e-8 relative (the issue's): the exact answer is reproduced up to round-off of the
// strain sums (~1e-16 per step over 400 steps) and the return's 1e-10 yield tolerance, which for
// linear hardening is met exactly after one Newton correction.
TEST_P(J2Paths, UniaxialStressMatchesClosedForm) {
  const PathCase c = GetParam();
  Point pt(c.plugin, law_params(c.plugin, c.H));
  const double K = kE / (3 * (1 - 2 * kNu));
  const double eps_y = kY0 / kE, eps_end = 20 * eps_y;
  const int steps = 400;
  const double dt = 1e-3, deps = eps_end / steps;
  const double plastic_ratio = -(kNu * c.H / kE + 0.5) / (1 + c.H / kE);
  double ea = 0.0, el = 0.0, worst = 0.0, worst_lateral = 0.0, worst_surface = 0.0;
  for (int k = 0; k < steps; ++k) {
    // The step from ea to ea + deps, split at the yield strain where it crosses it.
    const double a0 = ea, a1 = ea + deps;
    double dl = 0.0;
    if (a1 <= eps_y) dl = -kNu * deps;
    else if (a0 >= eps_y) dl = plastic_ratio * deps;
    else dl = -kNu * (eps_y - a0) + plastic_ratio * (a1 - eps_y);
    std::fill(pt.L, pt.L + 9, 0.0);
    pt.L[0] = deps / dt;
    pt.L[4] = pt.L[8] = dl / dt;
    ea = a1;
    el += dl;
    pt.density = kRho * (1.0 - (ea + 2 * el));
    pt.step(dt);
    const double sxx = pt.S[0] - pt.pressure, syy = pt.S[1] - pt.pressure;
    const double exact = ea <= eps_y ? kE * ea : kY0 + c.H * (ea - eps_y) / (1 + c.H / kE);
    worst = std::max(worst, std::abs(sxx - exact) / exact);
    worst_lateral = std::max(worst_lateral, std::abs(syy) / exact);
    if (ea > eps_y * (1 + 1e-9)) worst_surface = std::max(worst_surface, std::abs(pt.von_mises() - pt.yield()) / pt.yield());
  }
  EXPECT_GT(pt.eps_p(), 10 * eps_y);  // it did flow
  char line[300];
  std::snprintf(line, sizeof line,
                "material point %s H=%g uniaxial stress: max |sxx - exact|/exact %.2e, max |syy|/sxx %.2e, "
                "max |q - sigma_y|/sigma_y %.2e",
                c.plugin.c_str(), c.H, worst, worst_lateral, worst_surface);
  record(line);
  EXPECT_LT(worst, 1e-8) << line;
  EXPECT_LT(worst_lateral, 1e-8) << line;
  EXPECT_LT(worst_surface, 1e-10) << line;  // the return's tolerance (eq. 34)
}

// Pure shear: L with L_xy = L_yx = gdot/2 (no spin), tensor shear strain eps_xy = gdot t / 2.
// Answer: tau = 2 G eps_xy up to tau_y = sigma_y0/sqrt(3), then tau = (sigma_y0 + H eps_p)/sqrt(3)
// with eps_p = (2 sqrt(3) G eps_xy - sigma_y0)/(3 G + H); no pressure. Tolerance as above.
TEST_P(J2Paths, PureShearMatchesClosedForm) {
  const PathCase c = GetParam();
  Point pt(c.plugin, law_params(c.plugin, c.H));
  const double G = kE / (2 * (1 + kNu)), s3 = std::sqrt(3.0);
  const double exy_y = kY0 / s3 / (2 * G), exy_end = 20 * exy_y;
  const int steps = 400;
  const double dt = 1e-3, dexy = exy_end / steps;
  double exy = 0.0, worst = 0.0, worst_other = 0.0, worst_surface = 0.0;
  for (int k = 0; k < steps; ++k) {
    std::fill(pt.L, pt.L + 9, 0.0);
    pt.L[1] = pt.L[3] = dexy / dt;
    exy += dexy;
    pt.step(dt);
    const double tau = pt.S[3];
    const double exact = exy <= exy_y ? 2 * G * exy : (kY0 + c.H * (2 * s3 * G * exy - kY0) / (3 * G + c.H)) / s3;
    worst = std::max(worst, std::abs(tau - exact) / exact);
    for (int comp : {0, 1, 2, 4, 5}) worst_other = std::max(worst_other, std::abs(pt.S[comp]) / exact);
    worst_other = std::max(worst_other, std::abs(pt.pressure) / exact);
    if (exy > exy_y * (1 + 1e-9)) worst_surface = std::max(worst_surface, std::abs(pt.von_mises() - pt.yield()) / pt.yield());
  }
  EXPECT_GT(pt.eps_p(), 10 * kY0 / kE);
  char line[300];
  std::snprintf(line, sizeof line,
                "material point %s H=%g pure shear: max |tau - exact|/exact %.2e, other components %.2e, "
                "max |q - sigma_y|/sigma_y %.2e",
                c.plugin.c_str(), c.H, worst, worst_other, worst_surface);
  record(line);
  EXPECT_LT(worst, 1e-8) << line;
  EXPECT_LT(worst_other, 1e-8) << line;
  EXPECT_LT(worst_surface, 1e-10) << line;
}

INSTANTIATE_TEST_SUITE_P(PerfectAndLinearHardening, J2Paths,
                         ::testing::Values(PathCase{"elastoplastic", 0.0}, PathCase{"elastoplastic", 2e9},
                                           PathCase{"johnson_cook", 0.0}, PathCase{"johnson_cook", 2e9}),
                         [](const auto& info) {
                           return info.param.plugin + (info.param.H > 0 ? "_linear_hardening" : "_perfect");
                         });

/// Isochoric uniaxial deviatoric path L = rate diag(1, -1/2, -1/2): equivalent strain rate = rate.
void set_isochoric(Point& pt, double rate) {
  std::fill(pt.L, pt.L + 9, 0.0);
  pt.L[0] = rate;
  pt.L[4] = pt.L[8] = -0.5 * rate;
}

// Rate jump: ideal Johnson-Cook (B = 0), isothermal, strained at r1 until the flow is steady,
// then at r2. In steady flow the elastic strain is constant, so the plastic rate equals the applied
// one and q = A (1 + C ln(r/epsdot_0)); the ratio of the two plateaus is
// (1 + C ln(r2/epsdot_0)) / (1 + C ln(r1/epsdot_0)) (eq. 36). Each run also checks time scaling:
// f = 10 with rates 10x faster gives the same stress (eq. 25).
// Tolerance 1e-9 relative: each return meets the yield condition to 1e-10 sigma_y; the plateau is
// the fixed point of the step map, reached geometrically long before the 200 steps of each phase.
TEST(JohnsonCookPoint, RateJumpRatio) {
  const double A = 500e6, C = 0.03, rate0 = 1.0;
  for (const double f : {1.0, 10.0}) {
    Point pt("johnson_cook", {{"density", kRho}, {"youngs_modulus", kE}, {"poisson_ratio", kNu}, {"A", A}, {"C", C},
                              {"reference_strain_rate", rate0}, {"reference_temperature", 293.15},
                              {"melting_temperature", 1800.0}, {"output_fields", json::array({"yield_stress", "plastic_strain_rate"})}});
    const double r1 = 1e2, r2 = 1e4;
    auto phase = [&](double rate) {
      const double sim_rate = rate * f;
      const double dt = 2e-3 / sim_rate;  // 0.002 strain per step
      set_isochoric(pt, sim_rate);
      for (int k = 0; k < 200; ++k) {
        MaterialBatch b;
        b.count = 1;
        b.dt = dt;
        b.velocity_gradient = pt.L;
        b.density = &pt.density;
        b.deviatoric_stress = pt.S;
        b.pressure = &pt.pressure;
        b.fields = &pt.fields;
        b.time_scaling = f;
        pt.material->update_stress(b);
      }
      return pt.von_mises();
    };
    const double q1 = phase(r1), q2 = phase(r2);
    const double exact1 = A * (1 + C * std::log(r1 / rate0)), exact2 = A * (1 + C * std::log(r2 / rate0));
    const double ratio_error = std::abs((q2 / q1) / (exact2 / exact1) - 1.0);
    const double plateau_error = std::max(std::abs(q1 / exact1 - 1), std::abs(q2 / exact2 - 1));
    const double rate_out = pt.fields.f64("plastic_strain_rate")[0];
    char line[300];
    std::snprintf(line, sizeof line,
                  "johnson_cook rate jump %g -> %g 1/s (time scaling %g): ratio error %.2e, plateau error %.2e, "
                  "reported plastic rate %.6g 1/s",
                  r1, r2, f, ratio_error, plateau_error, rate_out);
    record(line);
    EXPECT_LT(ratio_error, 1e-9) << line;
    EXPECT_LT(plateau_error, 1e-9) << line;
    EXPECT_NEAR(rate_out, r2, 1e-9 * r2) << line;  // the physical rate (eq. 25), same reason
  }
}

// Rates below epsdot_0 never lower the strength (cut-off form of eq. 36): q = A exactly.
TEST(JohnsonCookPoint, RateTermNeverBelowOne) {
  const double A = 500e6;
  Point pt("johnson_cook", {{"density", kRho}, {"youngs_modulus", kE}, {"poisson_ratio", kNu}, {"A", A}, {"C", 0.05},
                            {"reference_strain_rate", 1.0}, {"reference_temperature", 293.15},
                            {"melting_temperature", 1800.0}, {"output_fields", json::array({"yield_stress"})}});
  set_isochoric(pt, 1e-3);
  for (int k = 0; k < 100; ++k) pt.step(1.0);  // 1e-3 strain per step at 1e-3 1/s
  EXPECT_GT(pt.eps_p(), 0.05);
  // Tolerance: the return's 1e-10 relative yield tolerance.
  EXPECT_NEAR(pt.von_mises(), A, 1e-10 * A);
}

// Temperature softening: ideal, rate-independent J-C held at temperature T and strained into
// steady flow: q = A (1 - Th^m), Th = (T - T_ref)/(T_m - T_ref) clamped to [0, 1] (eq. 36); below
// T_ref q = A; at and above T_m the strength is zero, and stress, plastic strain and heat stay
// finite (the whole trial deviator returns to zero, eq. 34 with sigma_y = 0).
// Tolerance 1e-10 relative: the return's yield tolerance; at T >= T_m the absolute stress must be
// zero to round-off of the trial stress (4 eps q*, the return's floor there).
TEST(JohnsonCookPoint, TemperatureSofteningAndMeltLimit) {
  const double A = 546e6, m = 1.57, Tr = 295.15, Tm = 750.15;  // AA7075-T6 (friction_extrusion.md)
  for (const double T : {250.0, Tr, 400.0, 550.0, 700.0, 749.0, Tm, 900.0}) {
    Point pt("johnson_cook", {{"density", 2810.0}, {"youngs_modulus", 71.7e9}, {"poisson_ratio", 0.33}, {"A", A},
                              {"m", m}, {"reference_temperature", Tr}, {"melting_temperature", Tm},
                              {"output_fields", json::array({"yield_stress"})}});
    pt.temperature = T;
    set_isochoric(pt, 1.0);
    double heat_sum = 0.0;
    for (int k = 0; k < 100; ++k) {
      pt.step(1e-3, true);
      heat_sum += pt.heat;
    }
    const double Th = std::clamp((T - Tr) / (Tm - Tr), 0.0, 1.0);
    const double exact = A * (1 - std::pow(Th, m));
    const double q = pt.von_mises();
    char line[200];
    std::snprintf(line, sizeof line, "johnson_cook softening T = %.2f K: q = %.6e Pa, exact %.6e Pa, eps_p %.4f", T, q,
                  exact, pt.eps_p());
    record(line);
    ASSERT_TRUE(std::isfinite(q) && std::isfinite(pt.eps_p()) && std::isfinite(heat_sum) && std::isfinite(pt.pressure))
        << line;
    if (exact > 0) {
      EXPECT_NEAR(q, exact, 1e-10 * exact) << line;
    } else {
      // 2G times one step's strain is the trial stress scale returned to zero each step.
      const double G = 71.7e9 / (2 * 1.33);
      EXPECT_LE(q, 4 * 2.2e-16 * 3 * G * 1e-3) << line;
      EXPECT_EQ(heat_sum, 0.0) << line;  // no strength, no plastic work
    }
  }
}

// Thermal expansion (eq. 17a): at rest (L = 0) a particle dT above the expansion's reference
// temperature is free of stress at the density rho0 / (1 + 3 alpha dT), and at rho0 it carries the
// pressure K 3 alpha dT of a fully restrained volume. Isothermal steps and alpha = 0 keep eq. 17.
// HX220 (friction_drilling.md): alpha 15e-6 1/K, E 210 GPa, nu 0.3; dT = 500 K. Tolerance: round-off
// of a pressure formed from densities of 7850 kg/m^3 (1e-12 relative, K = 175 GPa: 1e-12 K = 0.2 Pa).
TEST(JohnsonCookPoint, ThermalExpansionShiftsTheStressFreeDensity) {
  const double rho0 = 7850.0, E = 210e9, nu = 0.3, alpha = 15e-6, Tr = 293.15, dT = 500.0;
  const double K = E / (3 * (1 - 2 * nu));
  const json base = {{"density", rho0}, {"youngs_modulus", E}, {"poisson_ratio", nu}, {"A", 212.2e6},
                     {"reference_temperature", Tr}, {"melting_temperature", 1773.15}};
  json expanding = base;
  expanding["thermal_expansion"] = alpha;
  Point pt("johnson_cook", expanding);
  pt.temperature = Tr + dT;
  pt.step(1e-6, true);  // at rho0: restrained
  EXPECT_NEAR(pt.pressure, K * 3 * alpha * dT, 1e-12 * K) << "restrained";
  const double pressure_restrained = pt.pressure;
  pt.density = rho0 / (1 + 3 * alpha * dT);  // free
  pt.step(1e-6, true);
  EXPECT_NEAR(pt.pressure, 0.0, 1e-12 * K) << "free";
  pt.density = rho0;  // an isothermal step has no temperature, so no thermal strain (eq. 17)
  pt.step(1e-6, false);
  EXPECT_EQ(pt.pressure, 0.0);
  json shifted = expanding;  // stress-free at the particle's own temperature
  shifted["expansion_reference_temperature"] = Tr + dT;
  Point at_reference("johnson_cook", shifted);
  at_reference.temperature = Tr + dT;
  at_reference.step(1e-6, true);
  EXPECT_EQ(at_reference.pressure, 0.0);
  Point without("johnson_cook", base);  // alpha = 0 (the default): eq. 17 exactly
  without.temperature = Tr + dT;
  without.density = 1.001 * rho0;
  without.step(1e-6, true);
  EXPECT_EQ(without.pressure, K * (without.density - rho0) * (1.0 / rho0));  // eq. 17 as the plugin forms it
  char line[200];
  std::snprintf(line, sizeof line, "johnson_cook thermal expansion dT = %.0f K: restrained p = %.6e Pa (K 3 alpha dT = %.6e Pa)",
                dT, pressure_restrained, K * 3 * alpha * dT);
  record(line);
}

// Adiabatic heating (issue 4): 42CrMo4 strained uniaxially (isochoric path) at the reference rate
// with all plastic heat retained: dT/dt = beta sigma_y epsdot_p / (rho c) (eq. 37). The driver
// advances T by the material's heat source each step. Expected (issue): without softening
// T = 179.2, 352.8, 718.0 degC at eps_p = 0.5, 1, 2; with softening (m = 1.1) 173.0, 324.8, 595.2 degC.
// Tolerance 0.5 % of the temperature in degC (the issue's): the values are quoted to 0.1 degC and
// the explicit update (sigma_y of the step's start temperature) at 2e-4 strain per step adds
// far less (the heating is ~0.4 K per step at most).
TEST(JohnsonCookPoint, AdiabaticHeating42CrMo4) {
  const double rho = 7830, c = 460, beta = 0.9, T0 = 293.15, Tm = 1540 + 273.15;
  struct Expect {
    bool soften;
    double T[3];
  };
  for (const Expect& e : {Expect{false, {179.2, 352.8, 718.0}}, Expect{true, {173.0, 324.8, 595.2}}}) {
    // "Without softening": the melting temperature far away would still soften a little; m is
    // instead made so large that Th^m vanishes (Th < 0.5 here, 0.5^400 ~ 1e-120).
    const double m = e.soften ? 1.1 : 400.0;
    Point pt("johnson_cook", {{"density", rho}, {"youngs_modulus", 210e9}, {"poisson_ratio", 0.3}, {"A", 806e6},
                              {"B", 614e6}, {"n", 0.168}, {"C", 0.0089}, {"m", m}, {"reference_strain_rate", 1.0},
                              {"reference_temperature", T0}, {"melting_temperature", Tm}, {"taylor_quinney", beta},
                              {"conductivity", 42.6}, {"specific_heat", c}});
    pt.temperature = T0;
    const double dt = 2e-4;  // at 1 1/s: 2e-4 strain per step
    set_isochoric(pt, 1.0);
    const double targets[3] = {0.5, 1.0, 2.0};
    int next = 0;
    double prev_eps = 0.0, prev_T = T0;
    double worst = 0.0;
    std::string line_all = std::string("johnson_cook adiabatic heating 42CrMo4 ") + (e.soften ? "with" : "without") +
                           " softening:";
    while (next < 3) {
      pt.step(dt, true);
      pt.temperature += dt * pt.heat / c;
      const double eps = pt.eps_p();
      while (next < 3 && eps >= targets[next]) {
        // Linear interpolation of T between the two steps around the target strain.
        const double w = (targets[next] - prev_eps) / (eps - prev_eps);
        const double T_c = prev_T + w * (pt.temperature - prev_T) - 273.15;
        const double err = std::abs(T_c - e.T[next]) / e.T[next];
        worst = std::max(worst, err);
        char part[100];
        std::snprintf(part, sizeof part, " eps_p %.1f: %.2f degC (expected %.1f, %+.3f %%)", targets[next], T_c,
                      e.T[next], 100 * (T_c - e.T[next]) / e.T[next]);
        line_all += part;
        ++next;
      }
      prev_eps = eps;
      prev_T = pt.temperature;
    }
    record(line_all);
    EXPECT_LT(worst, 0.005) << line_all;
    // n = 0.168 < 1: the slope of eps_p^n is infinite at eps_p = 0, the bracket keeps Newton safe.
    EXPECT_EQ(pt.material->failed_returns(), 0) << line_all;
  }
}

// Elastic constants: E, nu and K, G give the same material; mixing them or giving neither is
// an input error naming the parameter.
TEST(ElastoplasticPoint, ElasticConstantsEitherPair) {
  const double E = 117e9, nu = 0.35, G = E / (2 * (1 + nu)), K = E / (3 * (1 - 2 * nu));
  auto a = make("elastoplastic", {{"density", 8930}, {"youngs_modulus", E}, {"poisson_ratio", nu}, {"yield_stress", 4e8}});
  auto b = make("elastoplastic", {{"density", 8930}, {"bulk_modulus", K}, {"shear_modulus", G}, {"yield_stress", 4e8}});
  // Tolerance: round-off of the two conversions.
  EXPECT_NEAR(a->wave_speed(), b->wave_speed(), 1e-12 * a->wave_speed());
  EXPECT_NEAR(a->shear_modulus(), b->shear_modulus(), 1e-12 * G);
  EXPECT_THROW(make("elastoplastic", {{"density", 8930}, {"youngs_modulus", E}, {"poisson_ratio", nu},
                                      {"bulk_modulus", K}, {"yield_stress", 4e8}}),
               InputError);
  EXPECT_THROW(make("elastoplastic", {{"density", 8930}, {"yield_stress", 4e8}}), InputError);
  EXPECT_THROW(make("elastoplastic", {{"density", 8930}, {"youngs_modulus", E}, {"yield_stress", 4e8}}), InputError);
  EXPECT_THROW(make("elastoplastic", {{"density", 8930}, {"youngs_modulus", E}, {"poisson_ratio", nu},
                                      {"yield_stress", 4e8}, {"output_fields", json::array({"stress"})}}),
               InputError);
}

// Optional outputs are allocated only when listed.
TEST(JohnsonCookPoint, DiagnosticFieldsOnlyWhenListed) {
  const json base = {{"density", kRho}, {"youngs_modulus", kE}, {"poisson_ratio", kNu}, {"A", kY0},
                     {"reference_temperature", 293.15}, {"melting_temperature", 1800.0}};
  auto plain = make("johnson_cook", base);
  ASSERT_EQ(plain->fields().size(), 1u);
  EXPECT_EQ(plain->fields()[0].name, field::plastic_strain);
  json listed = base;
  listed["output_fields"] = json::array({"plastic_strain_rate", "von_mises_stress", "yield_stress"});
  EXPECT_EQ(make("johnson_cook", listed)->fields().size(), 4u);
}

// Thermal properties linear in Th (eq. 38), AA7075 as printed in friction_extrusion.md:
// k = 166.1 - 50.1 Th, c = 795.8 - 350.4 Th, Th clamped to [0, 1].
// Tolerance 1e-12 relative: one multiply-add in double precision.
TEST(JohnsonCookPoint, ThermalPropertiesLinearInTh) {
  const double Tr = 295.15, Tm = 750.15;
  auto mat = make("johnson_cook", {{"density", 2810.0}, {"youngs_modulus", 71.7e9}, {"poisson_ratio", 0.33},
                                   {"A", 546e6}, {"m", 1.57}, {"reference_temperature", Tr}, {"melting_temperature", Tm},
                                   {"conductivity", 166.1}, {"conductivity_slope", -50.1}, {"specific_heat", 795.8},
                                   {"specific_heat_slope", -350.4}});
  ASSERT_TRUE(mat->conducts_heat());
  std::vector<double> T = {200.0, Tr, 400.0, 600.0, Tm, 1000.0}, k(T.size()), c(T.size());
  ThermalBatch b;
  b.count = T.size();
  b.temperature = T.data();
  b.conductivity = k.data();
  b.specific_heat = c.data();
  mat->thermal_properties(b);
  for (std::size_t i = 0; i < T.size(); ++i) {
    const double Th = std::clamp((T[i] - Tr) / (Tm - Tr), 0.0, 1.0);
    EXPECT_NEAR(k[i], 166.1 - 50.1 * Th, 1e-12 * 166.1) << T[i];
    EXPECT_NEAR(c[i], 795.8 - 350.4 * Th, 1e-12 * 795.8) << T[i];
  }
  // A slope that makes a property non-positive at T_m is an input error.
  EXPECT_THROW(make("johnson_cook", {{"density", 2810.0}, {"youngs_modulus", 71.7e9}, {"poisson_ratio", 0.33},
                                     {"A", 546e6}, {"reference_temperature", Tr}, {"melting_temperature", Tm},
                                     {"conductivity", 100.0}, {"specific_heat", 795.8}, {"specific_heat_slope", -900.0}}),
               InputError);
}

// Plastic heat of elastoplastic (eq. 37) in steady perfectly plastic flow: every step's plastic
// increment is the applied equivalent strain increment, so the heat source is
// beta sigma_y epsdot / rho exactly. Tolerance 1e-10 relative: the return's yield tolerance.
TEST(ElastoplasticPoint, PlasticHeatIsTaylorQuinneyTimesPlasticPower) {
  Point pt("elastoplastic", {{"density", kRho}, {"youngs_modulus", kE}, {"poisson_ratio", kNu}, {"yield_stress", kY0},
                             {"taylor_quinney", 0.85}, {"specific_heat", 460.0}, {"conductivity", 40.0}});
  pt.temperature = 300.0;
  set_isochoric(pt, 2.0);
  for (int k = 0; k < 20; ++k) pt.step(1e-3, true);  // 0.002 per step, yield strain 0.0015
  const double expected = 0.85 * kY0 * 2.0 / kRho;
  EXPECT_NEAR(pt.heat, expected, 1e-10 * expected);
  // Isothermal runs pass no heat source: nothing is written (no crash on the null pointer).
  pt.step(1e-3, false);
}

// The yield stress the material hands to friction laws (Coulomb-Tresca) is eq. 36 at the
// particle's state: after flow at T with eps_p, (A + B eps_p^n)(1 - Th^m), and R of the last
// plastic rate when that output is allocated. Tolerance 1e-12: the same arithmetic.
TEST(JohnsonCookPoint, YieldStressForFrictionLaws) {
  const double A = 112e6, B = 505e6, n = 0.42, C = 0.009, m = 1.68, Tr = 298.15, Tm = 1189.15, T = 700.0;
  Point pt("johnson_cook", {{"density", 8500.0}, {"youngs_modulus", 100e9}, {"poisson_ratio", 0.34}, {"A", A}, {"B", B},
                            {"n", n}, {"C", C}, {"m", m}, {"reference_temperature", Tr}, {"melting_temperature", Tm},
                            {"output_fields", json::array({"plastic_strain_rate"})}});
  pt.temperature = T;
  set_isochoric(pt, 50.0);
  for (int k = 0; k < 50; ++k) pt.step(1e-4, true);
  MaterialBatch b;
  b.count = 1;
  b.fields = &pt.fields;
  b.temperature = &pt.temperature;
  double out = 0.0;
  pt.material->yield_stress(b, &out);
  const double eps = pt.eps_p(), rate = pt.fields.f64("plastic_strain_rate")[0];
  const double Th = (T - Tr) / (Tm - Tr);
  const double expected = (A + B * std::pow(eps, n)) * (1 + C * std::log(rate)) * (1 - std::pow(Th, m));
  EXPECT_GT(rate, 1.0);
  EXPECT_NEAR(out, expected, 1e-12 * expected);
  // In steady flow this is the stress the return produced.
  EXPECT_NEAR(pt.von_mises(), expected, 1e-6 * expected);
}

// The parameter sets shipped next to the plugin (plugins/materials/johnson_cook/parameter_sets/,
// numbers from /work/shared/reference) are valid material sections: each loads, and flowing slowly
// (rate below epsdot_0) at T_ref gives the yield stress A of its set. Brass lacks the elastic data in
// the reference; the test adds placeholder ones (they do not enter the yield stress).
// Tolerance 1e-10: the return's yield tolerance.
TEST(JohnsonCookPoint, BundledParameterSetsLoad) {
  const std::string dir = std::string(SPHFORGE_SOURCE_DIR) + "/plugins/materials/johnson_cook/parameter_sets/";
  for (const std::string name : {"aa7075_t6", "hx220", "brass"}) {
    std::ifstream in(dir + name + ".json");
    ASSERT_TRUE(in) << name;
    json m = json::parse(in)["material"];
    ASSERT_EQ(m["plugin"], "johnson_cook") << name;
    m.erase("plugin");
    if (name == "brass") {
      m["density"] = 8400.0;
      m["youngs_modulus"] = 100e9;
      m["poisson_ratio"] = 0.34;
    }
    const LoadedPlugin& lp = loader().load(PluginKind::Material, "johnson_cook");
    const ParamValues v = validate_parameters(m, lp.descriptor->parameters, dir + name + ".json", "/material");
    Point pt("johnson_cook", m);
    EXPECT_EQ(pt.material->conducts_heat(), name != "brass") << name;
    pt.temperature = v.number("reference_temperature");
    // Isochoric flow at a tenth of epsdot_0 (R = 1), to 0.05 equivalent plastic strain at most.
    const double rate = 0.1 * v.number("reference_strain_rate");
    set_isochoric(pt, rate);
    const double yield_strain = v.number("A") / (v.number("youngs_modulus") / (2 * (1 + v.number("poisson_ratio")))) / 3;
    for (int k = 0; k < 3 && pt.eps_p() == 0.0; ++k) pt.step(2.0 * yield_strain / rate, true);
    const double hard = v.number("A") + v.number("B") * std::pow(pt.eps_p(), v.number("n"));
    EXPECT_GT(pt.eps_p(), 0.0) << name;
    EXPECT_NEAR(pt.von_mises(), hard, 1e-10 * hard) << name;
  }
}

// Many particles in one batch, as the core calls the plugin: every return of the interleaved,
// vectorized Johnson-Cook return (eqs. 34, 34a, 36a, 36b) must put the stress on the yield surface
// to the 1e-10, judged against eq. 36 evaluated here independently (std::pow, std::log) at
// the returned plastic strain and rate; elastic particles must lie inside the surface. The batch of
// 1,001 particles is not a multiple of the block or vector widths, so partial blocks and padded
// lanes are exercised. Per particle the strain increment (1e-7 to 1e-2 per step), the temperature
// (below T_ref to above T_m) and the load direction vary; the rate term straddles its cut-off.
// Parameter sets: brass (n = 0.42), HX220 (n = 0.35, C = 0), AA7075 (B = 0), 42CrMo4 (n = 0.168)
// and a convex hardening n = 1.5 (no curvature bound: every step evaluated).
// Tolerance 1e-10 relative, the return's yield tolerance (eq. 34), plus 1e-14 for the round-off by
// which the independent evaluation differs from the plugin's (pow against exp(n ln e), ~1e-15): a
// step accepted by the curvature bound (eq. 34a) may use the tolerance to the full. Accepting every
// Newton step (a zero bound) gives 4e-4 to 8e-2 here: the test catches a wrong bound.
TEST(JohnsonCookBlock, EveryReturnOnTheIndependentSurface) {
  struct Set {
    const char* name;
    double A, B, n, C, rate0, m, Tr, Tm;
  };
  const Set sets[] = {{"brass", 112e6, 505e6, 0.42, 0.009, 1.0, 1.68, 298.15, 1189.15},
                      {"hx220", 212.2e6, 409.2e6, 0.3524, 0.0, 0.01, 0.7521, 293.15, 1773.15},
                      {"aa7075", 546e6, 0.0, 1.0, 0.024, 1.0, 1.57, 295.15, 750.15},
                      {"42crmo4", 806e6, 614e6, 0.168, 0.0089, 1.0, 1.1, 293.15, 1813.15},
                      {"convex", 300e6, 400e6, 1.5, 0.02, 10.0, 1.0, 293.15, 1800.0}};
  const std::size_t count = 1001;
  for (const Set& c : sets) {
    const json params = {{"density", kRho}, {"youngs_modulus", kE}, {"poisson_ratio", kNu}, {"A", c.A}, {"B", c.B},
                         {"n", c.n}, {"C", c.C}, {"reference_strain_rate", c.rate0}, {"m", c.m},
                         {"reference_temperature", c.Tr}, {"melting_temperature", c.Tm},
                         {"output_fields", json::array({"plastic_strain_rate"})}};
    std::unique_ptr<Material> material = make("johnson_cook", params);
    FieldRegistry fields;
    for (const FieldInfo& f : material->fields()) fields.declare(f, "material");
    fields.allocate(count);
    material->initialize(fields, 0, count);
    std::vector<double> L(9 * count), S(6 * count, 0.0), p(count), rho(count, kRho), T(count), heat(count);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double dt = 1e-4;
    for (std::size_t i = 0; i < count; ++i) {
      const double rate = std::pow(10.0, -3.0 + 5.0 * u(rng));  // strain per step 1e-7 .. 1e-2
      const double shear = u(rng);
      L[9 * i] = rate;
      L[9 * i + 4] = L[9 * i + 8] = -0.5 * rate;
      L[9 * i + 1] = L[9 * i + 3] = shear * rate;
      T[i] = c.Tr + (c.Tm - c.Tr) * (-0.1 + 1.2 * u(rng));
    }
    const double G = kE / (2 * (1 + kNu)), Th_range = c.Tm - c.Tr;
    double worst = 0.0;
    long long plastic = 0, elastic_outside = 0;
    for (int step = 0; step < 30; ++step) {
      std::vector<double> eps_before(fields.f64(field::plastic_strain), fields.f64(field::plastic_strain) + count);
      MaterialBatch b;
      b.count = count;
      b.dt = dt;
      b.velocity_gradient = L.data();
      b.density = rho.data();
      b.deviatoric_stress = S.data();
      b.pressure = p.data();
      b.fields = &fields;
      b.temperature = T.data();
      b.heat_source = heat.data();
      material->update_stress(b);
      const double* eps = fields.f64(field::plastic_strain);
      const double* rate = fields.f64("plastic_strain_rate");
      for (std::size_t i = 0; i < count; ++i) {
        const double* s = &S[6 * i];
        const double q = std::sqrt(1.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] +
                                          2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])));
        const double Th = std::clamp((T[i] - c.Tr) / Th_range, 0.0, 1.0);
        const double theta = 1.0 - std::pow(Th, c.m);
        const double hard = c.A + (eps[i] > 0.0 ? c.B * std::pow(eps[i], c.n) : 0.0);
        const double R = (c.C != 0.0 && rate[i] > c.rate0) ? 1.0 + c.C * std::log(rate[i] / c.rate0) : 1.0;
        const double sigma_y = hard * R * theta;
        if (eps[i] > eps_before[i]) {
          ++plastic;
          // sigma_y = 0 (at or above T_m): the stress must vanish to round-off of the trial stress.
          const double err = sigma_y > 0.0 ? std::abs(q - sigma_y) / sigma_y : q / (3.0 * G);
          worst = std::max(worst, err);
        } else if (q > sigma_y * (1.0 + 1e-12)) {
          ++elastic_outside;
        }
      }
    }
    char line[300];
    std::snprintf(line, sizeof line,
                  "johnson_cook block (%s, %zu particles x 30 steps): %lld plastic returns, worst |q - sigma_y|/sigma_y "
                  "%.2e, elastic states outside the surface %lld, failed returns %lld",
                  c.name, count, plastic, worst, elastic_outside, material->failed_returns());
    record(line);
    EXPECT_GT(plastic, 10000) << line;  // most of the 30,030 updates flow plastically
    EXPECT_LT(worst, 1e-10 + 1e-14) << line;
    EXPECT_EQ(elastic_outside, 0) << line;
    EXPECT_EQ(material->failed_returns(), 0) << line;
  }
}

}  // namespace
