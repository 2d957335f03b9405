// Material plugin `johnson_cook`: linear elasticity with von Mises plasticity whose yield stress
// follows Johnson and Cook (1983),
//   sigma_y = (A + B eps_p^n) R(epsdot_p) Theta(T)                              (eq. 36)
//   R = max(1, 1 + C ln(epsdot_p / epsdot_0)),  Theta = 1 - Th^m,  Th = clamp((T - T_ref)/(T_m - T_ref), 0, 1)
// with the radial return of plugins/materials/common/j2_plasticity.hpp (eqs. 33-35; in blocks, with the
// step acceptance of eq. 34a by the curvature bound of eq. 36a and vector log/exp, eq. 36b), plastic heat
// (eq. 37) and thermal properties linear in Th (eq. 38). docs/theory.md section 5.
// Parameter sets of the bundled processes (AA7075-T6, HX220, brass): docs/theory.md section 5,
// from /work/shared/reference (friction_extrusion.md, friction_drilling.md,
// friction_stir_back_extrusion.md).
#include <algorithm>
#include <cmath>
#include <limits>

#include "../common/j2_plasticity.hpp"
#include "../common/failure.hpp"
#include "../common/optional_outputs.hpp"
#include "../common/vector_math.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

/// The Johnson-Cook yield law at one particle: strain hardening and rate term of eq. 36 for the
/// trial increment d, with the thermal factor fixed over the step (the temperature is the step's).
struct JohnsonCookLaw {
  double A, B, n, C, rate_ref, m;

  /// sigma_y and its slope d sigma_y / d d, with the factors they are made of (kept for the curvature
  /// bound below, which then needs no further logarithm or power).
  struct Value {
    double stress, slope;  ///< sigma_y (Pa), d sigma_y / d d (Pa)
    double hard, dhard;    ///< A + B e^n and its derivative n B e^(n-1), e = eps_p + d
    double R, dR;          ///< rate factor and d R / d d (0 below the cut-off)
    double inv_e, inv_d;   ///< 1/e and 1/d where they were needed (else 0), reused by the bound
  };

  /// en[i] = e[i]^n = exp(n ln e[i]) for the first `count` of `padded` entries (eq. 36b), through the
  /// vector functions; entries with e <= 0 (no plastic strain yet) get 0, unused by combine().
  /// `e` is read only below `count`; `work` is scratch of `padded` entries.
  void powers(int padded, int count, const double* e, double* en, double* work) const {
    for (int i = 0; i < padded; ++i) work[i] = i < count && e[i] > 0.0 ? e[i] : 1.0;
    vmath::log(padded, work, work);
    for (int i = 0; i < padded; ++i) work[i] *= n;
    vmath::exp(padded, work, en);
    for (int i = 0; i < count; ++i)
      if (!(e[i] > 0.0)) en[i] = 0.0;
  }

  /// Whether the rate term is on at the increment d: epsdot_p = d / (dt f) above epsdot_0 (eq. 36);
  /// never with C = 0 (rate independent: the logarithm is never evaluated).
  bool rate_on(double d, double inv_dt_phys) const { return C != 0.0 && d * inv_dt_phys > rate_ref; }

  /// sigma_y and d sigma_y / d d (eq. 36) from the transcendental parts computed by the caller:
  /// en = e^n at e = eps_p + d (unused when B = 0 or e = 0) and log_rate = ln(epsdot_p / epsdot_0)
  /// (unused when the rate term is off).
  Value combine(double e, double en, double d, bool rate, double log_rate, double theta) const {
    double hard = A, dhard = 0.0, inv_e = 0.0;
    if (B != 0.0 && e > 0.0) {
      inv_e = 1.0 / e;
      hard += B * en;
      dhard = B * n * en * inv_e;
    }
    double R = 1.0, dR = 0.0, inv_d = 0.0;
    if (rate) {  // below the cut-off R = 1 (never below 1)
      inv_d = 1.0 / d;
      R = 1.0 + C * log_rate;
      dR = C * inv_d;  // d/dd [C ln(d / (dt f epsdot_0))]
    }
    return {hard * R * theta, (dhard * R + hard * dR) * theta, hard, dhard, R, dR, inv_e, inv_d};
  }

  /// M >= |d^2 sigma_y / d d^2| for all increments between d and d_next (eq. 36a), from the factors
  /// at d: sigma_y'' = Theta (h'' R + 2 h' R' + h R''), h = A + B e^n, R = 1 + C ln(d/d_ref).
  /// For 0 < n <= 1, |h''| and h' fall and h rises with e; R' = C/d and |R''| = C/d^2 fall and R
  /// rises with d; so each factor takes its largest value at one end of the interval. The end not
  /// evaluated is bounded without a power: (e/e_a)^(2-n) <= (e/e_a)^2 and (e/e_a)^(1-n) <= e/e_a for
  /// e_a <= e, and the concave h and R lie below their tangents at d. Infinity (no bound: the return
  /// evaluates d_next) for n > 1 and when the rate cut-off lies between d and d_next.
  double curvature_bound(double eps, const Value& y, double d, double d_next, double inv_dt_phys, double theta) const {
    constexpr double no_bound = std::numeric_limits<double>::infinity();
    if (B != 0.0 && n > 1.0) return no_bound;
    const double a = std::min(d, d_next), step = d_next - d;  // a: the interval's lower end
    double R_max = y.R, dR_max = 0.0, d2R_max = 0.0;
    if (C != 0.0) {
      const bool rate_on = d * inv_dt_phys > rate_ref;
      if (rate_on != (d_next * inv_dt_phys > rate_ref)) return no_bound;
      if (rate_on) {
        const double inv_a = step > 0.0 ? y.inv_d : 1.0 / a;  // a = d: known from the evaluation
        dR_max = C * inv_a;
        d2R_max = dR_max * inv_a;
        if (step > 0.0) R_max = y.R + y.dR * step;
      }
    }
    double h_max = y.hard, dh_max = y.dhard, d2h_max = 0.0;
    if (B != 0.0) {
      const double e_a = eps + a;
      if (!(e_a > 0.0) || !(y.inv_e > 0.0)) return no_bound;
      const double inv_e_a = step > 0.0 ? y.inv_e : 1.0 / e_a;  // a = d: e_a = e
      const double ratio = step > 0.0 ? 1.0 : (eps + d) * inv_e_a;  // e / e_a >= 1
      dh_max = y.dhard * ratio;
      d2h_max = (1.0 - n) * dh_max * inv_e_a;  // n (1 - n) B e^(n-2) = (1 - n) h' / e, times (e/e_a)^2
      if (step > 0.0) h_max = y.hard + y.dhard * step;
    }
    return theta * (d2h_max * R_max + 2.0 * dh_max * dR_max + h_max * d2R_max);
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
        volumetric_expansion_(3.0 * p.number("thermal_expansion")),
        T_expansion_(p.number("expansion_reference_temperature") >= 0.0 ? p.number("expansion_reference_temperature")
                                                                          : T_ref_),
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

  /// Theta = 1 - Th^m (eq. 36) of `count` (<= j2::kReturnBlock) particles, T their temperatures (null
  /// when isothermal: the law at T_ref, Theta = 1). Th clamped to [0, 1]: below T_ref no extra strength,
  /// at or above T_m none at all (no power of a negative number, no NaN); between, Th^m = exp(m ln Th)
  /// through the vector functions (eq. 36b). `work`: scratch of vmath::padded(count) entries.
  void thermal_factors(int count, const double* T, double* theta, double* work) const {
    if (!T) {
      std::fill(theta, theta + count, 1.0);
      return;
    }
    const int padded = vmath::padded(count);
    const double inv_range = 1.0 / (T_melt_ - T_ref_);
    for (int k = 0; k < padded; ++k) {
      const double Th = k < count ? (T[k] - T_ref_) * inv_range : 0.5;  // 0.5: padding
      theta[k] = Th;
      work[k] = (Th > 0.0 && Th < 1.0) ? Th : 0.5;
    }
    vmath::log(padded, work, work);
    for (int k = 0; k < padded; ++k) work[k] *= law_.m;
    vmath::exp(padded, work, work);
    for (int k = 0; k < count; ++k) theta[k] = theta[k] <= 0.0 ? 1.0 : (theta[k] >= 1.0 ? 0.0 : 1.0 - work[k]);
  }

  void update_stress(MaterialBatch& b) override {
    const j2::OptionalOutputs::Arrays out = outputs_.arrays(b);
    const double two_g_dt = 2.0 * G_ * b.dt, three_g = 3.0 * G_;
    const double inv_dt = 1.0 / b.dt, inv_dt_phys = inv_dt / b.time_scaling;
    const double beta = taylor_quinney_, inv_rho0 = 1.0 / rho0_;
    const JohnsonCookLaw law = law_;
    const double* T = b.temperature;  // null when isothermal: the law at T_ref (Theta = 1)
    // Thermal expansion (eq. 17a) only in a thermal scene and when the case gives alpha > 0.
    const double expansion = T ? volumetric_expansion_ : 0.0, T_expansion = T_expansion_;
    long long failed = 0;
    // Blocks of particles: the trial states first, then the interleaved returns of the block's
    // plastic particles (plugins/materials/common/j2_plasticity.hpp explains why); the logarithms
    // and exponentials of a block go through the vector functions of vector_math.hpp (eq. 36b).
#pragma omp parallel for schedule(static) reduction(+ : failed)
    for (std::size_t first = 0; first < b.count; first += j2::kReturnBlock) {
      const int count = static_cast<int>(std::min<std::size_t>(b.count - first, j2::kReturnBlock));
      const int padded = vmath::padded(count);
      alignas(64) double q[j2::kReturnBlock], eps[j2::kReturnBlock], theta[j2::kReturnBlock];
      alignas(64) double eps_n[j2::kReturnBlock], work[j2::kReturnBlock];
      for (int k = 0; k < count; ++k) {
        const std::size_t i = first + k;
        double* s = b.deviatoric_stress + 6 * i;
        j2::elastic_predictor(b.velocity_gradient + 9 * i, two_g_dt, s);  // eq. 15
        q[k] = j2::von_mises(s);
        eps[k] = out.plastic_strain[i];
        b.pressure[i] = expansion == 0.0 ? j2::linear_pressure(K_, b.density[i], rho0_, inv_rho0)  // eq. 17
                                         : j2::thermal_linear_pressure(K_, b.density[i], rho0_, inv_rho0, expansion,
                                                                       T[i] - T_expansion);  // eq. 17a
      }
      thermal_factors(count, T ? T + first : nullptr, theta, work);
      // eps_p^n for the elastic check (eq. 36 at d = 0).
      if (law.B != 0.0) law.powers(padded, count, eps, eps_n, work);
      else std::fill(eps_n, eps_n + count, 0.0);
      // Elastic check at zero plastic rate (R = 1): the yield stress the trial state must exceed.
      j2::PlasticLanes lanes;
      double theta_of[j2::kReturnBlock];  // Theta of each plastic lane
      for (int k = 0; k < count; ++k) {
        const double yield = law.combine(eps[k], eps_n[k], 0.0, false, 0.0, theta[k]).stress;
        if (q[k] > yield)
          theta_of[lanes.add(first + k, q[k], eps[k], yield)] = theta[k];
        else
          j2::elastic_outputs(out, first + k, q[k], yield);
      }
      // Eq. 36 at the plastic lanes, a whole iteration's lanes at once, with the curvature bound
      // (eq. 36a) for the return's step acceptance.
      struct LaneLaw {
        using Value = JohnsonCookLaw::Value;
        const JohnsonCookLaw& law;
        const j2::PlasticLanes& lanes;
        const double* theta;
        double inv_dt_phys;
        void evaluate(int n, const int* lane, const double* d, Value* y) const {
          const int padded = vmath::padded(n);
          alignas(64) double e[j2::kReturnBlock], en[j2::kReturnBlock], log_rate[j2::kReturnBlock];
          alignas(64) double work[j2::kReturnBlock];
          for (int a = 0; a < n; ++a) e[a] = lanes.eps[lane[a]] + d[lane[a]];
          if (law.B != 0.0) law.powers(padded, n, e, en, work);
          else std::fill(en, en + n, 0.0);
          if (law.C != 0.0) {
            for (int a = 0; a < padded; ++a)
              log_rate[a] = a < n && law.rate_on(d[lane[a]], inv_dt_phys) ? d[lane[a]] * inv_dt_phys / law.rate_ref : 1.0;
            vmath::log(padded, log_rate, log_rate);
          }
          for (int a = 0; a < n; ++a) {
            const int k = lane[a];
            const bool rate = law.rate_on(d[k], inv_dt_phys);
            y[k] = law.combine(e[a], en[a], d[k], rate, rate ? log_rate[a] : 0.0, theta[k]);
          }
        }
        double curvature_bound(int k, const Value& y, double d, double d_next) const {
          return law.curvature_bound(lanes.eps[k], y, d, d_next, inv_dt_phys, theta[k]);
        }
      };
      failed += j2::plastic_correction(b, out, lanes, three_g, inv_dt, beta, LaneLaw{law, lanes, theta_of, inv_dt_phys});
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
    for (std::size_t first = 0; first < b.count; first += j2::kReturnBlock) {
      const int count = static_cast<int>(std::min<std::size_t>(b.count - first, j2::kReturnBlock));
      alignas(64) double theta[j2::kReturnBlock], eps_n[j2::kReturnBlock], work[j2::kReturnBlock];
      thermal_factors(count, b.temperature ? b.temperature + first : nullptr, theta, work);
      if (law_.B != 0.0) law_.powers(vmath::padded(count), count, eps_p + first, eps_n, work);
      else std::fill(eps_n, eps_n + count, 0.0);
      for (int k = 0; k < count; ++k) {
        const std::size_t i = first + k;
        out[i] = law_.combine(eps_p[i], eps_n[k], 0.0, false, 0.0, theta[k]).stress;
        if (rate && law_.C != 0.0 && rate[i] > law_.rate_ref) out[i] *= 1.0 + law_.C * std::log(rate[i] / law_.rate_ref);
      }
    }
  }

  long long failed_returns() const override { return failed_; }

 private:
  double rho0_, taylor_quinney_, T_ref_, T_melt_, k0_, k1_, c0_, c1_;
  double volumetric_expansion_, T_expansion_;  // 3 alpha (1/K) and the stress-free temperature (K), eq. 17a
  double G_ = 0, K_ = 0;
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
          ParamSpec::number("thermal_expansion", "1/K", 0.0,
                            "linear thermal expansion coefficient alpha (thermal cases; 0: none), eq. 17a", 0.0),
          ParamSpec::number("expansion_reference_temperature", "K", -1.0,
                            "temperature at which the material is free of thermal strain (-1: reference_temperature)"),
          j2::OptionalOutputs::spec(),
          j2::FailureCriterion::spec(),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
