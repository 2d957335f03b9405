// Material plugin `johnson_cook`: linear elasticity with von Mises plasticity whose yield stress
// follows Johnson and Cook (1983),
//   sigma_y = (A + B eps_p^n) R(epsdot_p) Theta(T)                              (eq. 36)
//   R = max(1, 1 + C ln(epsdot_p / epsdot_0)),  Theta = 1 - Th^m,  Th = clamp((T - T_ref)/(T_m - T_ref), 0, 1)
// with the radial return of plugins/materials/common/j2_plasticity.hpp (eqs. 33-35), plastic heat
// (eq. 37) and thermal properties linear in Th (eq. 38). docs/theory.md section 5.
// Parameter sets of the bundled processes (AA7075-T6, HX220, brass): docs/theory.md section 5,
// from /work/shared/reference (friction_extrusion.md, friction_drilling.md,
// friction_stir_back_extrusion.md).
#include <algorithm>
#include <cmath>

#include "../common/j2_plasticity.hpp"
#include "../common/failure.hpp"
#include "../common/optional_outputs.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

/// The Johnson-Cook yield law at one particle: strain hardening and rate term of eq. 36 for the
/// trial increment d, with the thermal factor fixed over the step (the temperature is the step's).
struct JohnsonCookLaw {
  double A, B, n, C, rate_ref, m;

  /// Thermal factor Theta = 1 - Th^m (eq. 36); Th clamped to [0, 1]: below T_ref no extra
  /// strength, at or above T_m none at all (no pow of a negative number, no NaN).
  static double softening(double Th, double m) {
    if (Th <= 0.0) return 1.0;
    if (Th >= 1.0) return 0.0;
    return 1.0 - std::pow(Th, m);
  }

  /// sigma_y and d sigma_y / d d at eps_p + d and the plastic rate d / dt_phys (eq. 36).
  /// inv_dt_phys = 1 / (dt f): the rate term sees the physical rate (eq. 25).
  j2::YieldValue operator()(double eps, double d, double inv_dt_phys, double theta) const {
    const double e = eps + d;
    double hard = A, dhard = 0.0;
    if (B != 0.0 && e > 0.0) {
      const double en = std::pow(e, n);  // one pow serves the value and the slope
      hard += B * en;
      dhard = B * n * en / e;
    }
    double R = 1.0, dR = 0.0;
    if (C != 0.0) {  // C = 0: rate independent, the logarithm is never evaluated
      const double rate = d * inv_dt_phys;
      if (rate > rate_ref) {  // cut-off: R = 1 for epsdot_p <= epsdot_0 (never below 1)
        R = 1.0 + C * std::log(rate / rate_ref);
        dR = C / d;  // d/dd [C ln(d / (dt f epsdot_0))]
      }
    }
    return {hard * R * theta, (dhard * R + hard * dR) * theta};
  }
};

class JohnsonCook final : public Material {
 public:
  explicit JohnsonCook(const ParamValues& p)
      : rho0_(p.number("density")),
        taylor_quinney_(p.number("taylor_quinney")),
        T_ref_(p.number("reference_temperature")),
        T_melt_(p.number("melting_temperature")),
        k0_(p.number("conductivity")),
        k1_(p.number("conductivity_slope")),
        c0_(p.number("specific_heat")),
        c1_(p.number("specific_heat_slope")),
        outputs_(p),
        failure_(p) {
    law_ = {p.number("A"), p.number("B"), p.number("n"), p.number("C"), p.number("reference_strain_rate"), p.number("m")};
    const j2::ElasticModuli moduli = j2::moduli_from_youngs(p.number("youngs_modulus"), p.number("poisson_ratio"));
    K_ = moduli.bulk;  // eq. 33
    G_ = moduli.shear;
    if (!(T_melt_ > T_ref_)) p.fail("melting_temperature", "must exceed reference_temperature");
    if (law_.B > 0.0 && !(law_.n > 0.0)) p.fail("n", "must be positive when B > 0");
    // Both thermal properties must stay positive over 0 <= Th <= 1 (eq. 38).
    if (c0_ > 0.0 && !(c0_ + c1_ > 0.0)) p.fail("specific_heat_slope", "makes the specific heat non-positive at the melting temperature");
    if (k0_ > 0.0 && !(k0_ + k1_ > 0.0)) p.fail("conductivity_slope", "makes the conductivity non-positive at the melting temperature");
  }

  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> f = outputs_.fields();
    failure_.add_fields(f);
    return f;
  }
  double reference_density() const override { return rho0_; }
  double wave_speed() const override { return std::sqrt((K_ + 4.0 * G_ / 3.0) / rho0_); }
  double shear_modulus() const override { return G_; }
  bool conducts_heat() const override { return c0_ > 0.0 && k0_ > 0.0; }

  /// k = k0 + k1 Th, c = c0 + c1 Th (eq. 38), Th clamped to [0, 1] as in eq. 36.
  void thermal_properties(ThermalBatch& b) const override {
    const double inv = 1.0 / (T_melt_ - T_ref_);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < b.count; ++i) {
      const double Th = std::clamp((b.temperature[i] - T_ref_) * inv, 0.0, 1.0);
      b.conductivity[i] = k0_ + k1_ * Th;
      b.specific_heat[i] = c0_ + c1_ * Th;
    }
  }

  void update_stress(MaterialBatch& b) override {
    const j2::OptionalOutputs::Arrays out = outputs_.arrays(b);
    const double two_g_dt = 2.0 * G_ * b.dt, three_g = 3.0 * G_;
    const double inv_dt = 1.0 / b.dt, inv_dt_phys = inv_dt / b.time_scaling;
    const double inv_range = 1.0 / (T_melt_ - T_ref_), beta = taylor_quinney_;
    const JohnsonCookLaw law = law_;
    const double* T = b.temperature;  // null when isothermal: the law at T_ref (Theta = 1)
    long long failed = 0;
#pragma omp parallel for schedule(static) reduction(+ : failed)
    for (std::size_t i = 0; i < b.count; ++i) {
      double* s = b.deviatoric_stress + 6 * i;
      j2::elastic_predictor(b.velocity_gradient + 9 * i, two_g_dt, s);  // eq. 15
      const double q = j2::von_mises(s);
      const double eps = out.plastic_strain[i];
      const double theta = T ? JohnsonCookLaw::softening((T[i] - T_ref_) * inv_range, law.m) : 1.0;
      // Elastic check at zero plastic rate (R = 1): the yield stress the trial state must exceed.
      const double yield = law(eps, 0.0, inv_dt_phys, theta).stress;
      const auto johnson_cook = [&](double d) { return law(eps, d, inv_dt_phys, theta); };  // eq. 36
      failed += j2::plastic_correction(b, out, i, s, q, eps, yield, three_g, inv_dt, beta, johnson_cook) ? 0 : 1;
      b.pressure[i] = j2::linear_pressure(K_, b.density[i], rho0_);  // eq. 17
    }
    failed_ += failed;
    failure_.update(b, out.plastic_strain);  // eq. 110
  }

  /// Yield stress for friction laws (Coulomb-Tresca): eq. 36 at the particle's plastic strain and
  /// temperature, with the rate term of its last plastic rate when that output is allocated, else R = 1.
  void yield_stress(const MaterialBatch& b, double* out) const override {
    const double* eps_p = b.fields->f64(field::plastic_strain) + b.first;
    const double* rate = b.fields->f64_if(j2::output::plastic_strain_rate);
    if (rate) rate += b.first;
    const double inv_range = 1.0 / (T_melt_ - T_ref_);
    for (std::size_t i = 0; i < b.count; ++i) {
      const double theta = b.temperature ? JohnsonCookLaw::softening((b.temperature[i] - T_ref_) * inv_range, law_.m) : 1.0;
      out[i] = law_(eps_p[i], 0.0, 1.0, theta).stress;
      if (rate && law_.C != 0.0 && rate[i] > law_.rate_ref) out[i] *= 1.0 + law_.C * std::log(rate[i] / law_.rate_ref);
    }
  }

  long long failed_returns() const override { return failed_; }

 private:
  double rho0_, taylor_quinney_, T_ref_, T_melt_, k0_, k1_, c0_, c1_, G_ = 0, K_ = 0;
  JohnsonCookLaw law_{};
  j2::OptionalOutputs outputs_;
  j2::FailureCriterion failure_;
  long long failed_ = 0;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<JohnsonCook>(
      "johnson_cook", "0.1.0",
      "Johnson-Cook thermo-visco-plasticity (von Mises), linear elasticity, thermal properties linear in Th",
      {
          ParamSpec::number("density", "kg/m^3", std::nullopt, "reference density rho0", 1e-6),
          ParamSpec::number("youngs_modulus", "Pa", std::nullopt, "Young's modulus E", 1e-6),
          ParamSpec::number("poisson_ratio", "1", std::nullopt, "Poisson's ratio nu", -0.999, 0.4999),
          ParamSpec::number("A", "Pa", std::nullopt, "initial yield stress A", 0.0),
          ParamSpec::number("B", "Pa", 0.0, "strain hardening modulus B (0: ideal plasticity)", 0.0),
          ParamSpec::number("n", "1", 1.0, "strain hardening exponent n", 0.0),
          ParamSpec::number("C", "1", 0.0, "strain rate coefficient C (0: rate independent, no rate term)", 0.0),
          ParamSpec::number("reference_strain_rate", "1/s", 1.0, "reference plastic strain rate epsdot_0", 1e-30),
          ParamSpec::number("m", "1", 1.0, "thermal softening exponent m", 1e-6),
          ParamSpec::number("reference_temperature", "K", std::nullopt, "T_ref (room temperature of the fit)", 0.0),
          ParamSpec::number("melting_temperature", "K", std::nullopt, "T_m: no strength at or above it", 0.0),
          ParamSpec::number("taylor_quinney", "1", 0.9, "fraction beta of the plastic work turned into heat", 0.0, 1.0),
          ParamSpec::number("conductivity", "W/(m*K)", 0.0, "k0 of k = k0 + k1 Th (thermal cases)", 0.0),
          ParamSpec::number("conductivity_slope", "W/(m*K)", 0.0, "k1 of k = k0 + k1 Th"),
          ParamSpec::number("specific_heat", "J/(kg*K)", 0.0, "c0 of c = c0 + c1 Th (thermal cases; 0: none)", 0.0),
          ParamSpec::number("specific_heat_slope", "J/(kg*K)", 0.0, "c1 of c = c0 + c1 Th"),
          j2::OptionalOutputs::spec(),
          j2::FailureCriterion::spec(),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
