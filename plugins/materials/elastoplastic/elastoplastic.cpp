// Material plugin `elastoplastic`: isotropic linear elasticity (E, nu or K, G) with von Mises (J2)
// plasticity, perfectly plastic or with linear isotropic hardening, and a linear equation of state.
// docs/theory.md section 5, eqs. 15-17 and 33-35; the return mapping is the shared one of
// plugins/materials/common/j2_plasticity.hpp.
#include <algorithm>
#include <cmath>

#include "../common/j2_plasticity.hpp"
#include "../common/failure.hpp"
#include "../common/optional_outputs.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class Elastoplastic final : public Material {
 public:
  explicit Elastoplastic(const ParamValues& p)
      : rho0_(p.number("density")),
        yield0_(p.number("yield_stress")),
        hardening_(p.number("hardening_modulus")),
        taylor_quinney_(p.number("taylor_quinney")),
        conductivity_(p.number("conductivity")),
        specific_heat_(p.number("specific_heat")),
        outputs_(p),
        failure_(p) {
    const double E = p.number("youngs_modulus"), nu = p.number("poisson_ratio");
    const double K = p.number("bulk_modulus"), G = p.number("shear_modulus");
    // Exactly one pair of elastic constants (0 / -1 mark a constant that was not given).
    if (E > 0.0) {
      if (K > 0.0 || G > 0.0) p.fail("bulk_modulus", "give either youngs_modulus and poisson_ratio, or bulk_modulus and shear_modulus, not both");
      if (nu == -1.0) p.fail("poisson_ratio", "is required with youngs_modulus");
      const j2::ElasticModuli moduli = j2::moduli_from_youngs(E, nu);  // eq. 33
      K_ = moduli.bulk;
      G_ = moduli.shear;
    } else {
      if (!(K > 0.0)) p.fail("bulk_modulus", "give youngs_modulus and poisson_ratio, or bulk_modulus and shear_modulus");
      if (!(G > 0.0)) p.fail("shear_modulus", "is required with bulk_modulus");
      if (nu != -1.0) p.fail("poisson_ratio", "belongs to youngs_modulus; with bulk_modulus and shear_modulus leave it out");
      K_ = K;
      G_ = G;
    }
  }

  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> f = outputs_.fields();
    failure_.add_fields(f);
    return f;
  }
  double reference_density() const override { return rho0_; }
  double wave_speed() const override { return std::sqrt((K_ + 4.0 * G_ / 3.0) / rho0_); }
  double shear_modulus() const override { return G_; }
  bool conducts_heat() const override { return specific_heat_ > 0.0; }
  void thermal_properties(ThermalBatch& b) const override {
    std::fill(b.conductivity, b.conductivity + b.count, conductivity_);
    std::fill(b.specific_heat, b.specific_heat + b.count, specific_heat_);
  }

  void update_stress(MaterialBatch& b) override {
    const j2::OptionalOutputs::Arrays out = outputs_.arrays(b);
    const double two_g_dt = 2.0 * G_ * b.dt, three_g = 3.0 * G_;
    const double y0 = yield0_, H = hardening_, beta = taylor_quinney_, inv_dt = 1.0 / b.dt, inv_rho0 = 1.0 / rho0_;
    long long failed = 0;
    // Blocks of particles: the trial states first, then the returns of the block's plastic particles
    // (plugins/materials/common/j2_plasticity.hpp).
#pragma omp parallel for schedule(static) reduction(+ : failed)
    for (std::size_t first = 0; first < b.count; first += j2::kReturnBlock) {
      const std::size_t last = std::min(b.count, first + j2::kReturnBlock);
      j2::PlasticLanes lanes;
      for (std::size_t i = first; i < last; ++i) {
        double* s = b.deviatoric_stress + 6 * i;
        j2::elastic_predictor(b.velocity_gradient + 9 * i, two_g_dt, s);  // eq. 15
        const double q = j2::von_mises(s);
        const double eps = out.plastic_strain[i];
        const double yield = y0 + H * eps;  // eq. 33a
        if (q > yield)
          lanes.add(i, q, eps, yield);
        else
          j2::elastic_outputs(out, i, q, yield);
        b.pressure[i] = j2::linear_pressure(K_, b.density[i], rho0_, inv_rho0);  // eq. 17
      }
      // Linear hardening: sigma_y(d) = y0 + H (eps_p + d), slope H; the Newton return of eq. 34 is
      // exact after one correction (g is linear in d), which its zero curvature (eq. 34a) accepts
      // without a second evaluation.
      struct LinearHardening {
        const j2::PlasticLanes& lanes;
        double H;
        using Value = j2::YieldValue;
        void evaluate(int n, const int* lane, const double* d, Value* y) const {
          for (int a = 0; a < n; ++a) y[lane[a]] = {lanes.yield0[lane[a]] + H * d[lane[a]], H};
        }
        double curvature_bound(int, const j2::YieldValue&, double, double) const { return 0.0; }
      };
      failed += j2::plastic_correction(b, out, lanes, three_g, inv_dt, beta, LinearHardening{lanes, H});
    }
    failed_ += failed;
    failure_.update(b, out.plastic_strain);  // eq. 110
  }

  void yield_stress(const MaterialBatch& b, double* out) const override {
    const double* eps_p = b.fields->f64(field::plastic_strain) + b.first;
    for (std::size_t i = 0; i < b.count; ++i) out[i] = yield0_ + hardening_ * eps_p[i];
  }

  long long failed_returns() const override { return failed_; }

 private:
  double rho0_, yield0_, hardening_, taylor_quinney_, conductivity_, specific_heat_, G_ = 0, K_ = 0;
  j2::OptionalOutputs outputs_;
  j2::FailureCriterion failure_;
  long long failed_ = 0;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Elastoplastic>(
      "elastoplastic", "0.2.0",
      "linear elasticity with von Mises plasticity, perfectly plastic or linear isotropic hardening",
      {
          ParamSpec::number("density", "kg/m^3", std::nullopt, "reference density rho0 (mass-scaled if wanted)", 1e-6),
          ParamSpec::number("youngs_modulus", "Pa", 0.0, "Young's modulus E (with poisson_ratio; or give K and G)", 0.0),
          ParamSpec::number("poisson_ratio", "1", -1.0, "Poisson's ratio nu (with youngs_modulus; -1: not given)", -1.0,
                            0.4999),
          ParamSpec::number("bulk_modulus", "Pa", 0.0, "bulk modulus K (with shear_modulus, instead of E and nu)", 0.0),
          ParamSpec::number("shear_modulus", "Pa", 0.0, "shear modulus G (with bulk_modulus, instead of E and nu)", 0.0),
          ParamSpec::number("yield_stress", "Pa", std::nullopt, "initial yield stress sigma_y0", 0.0),
          ParamSpec::number("hardening_modulus", "Pa", 0.0, "linear isotropic hardening modulus H (0: perfectly plastic)", 0.0),
          ParamSpec::number("taylor_quinney", "1", 0.9, "fraction beta of the plastic work turned into heat (thermal cases)",
                            0.0, 1.0),
          ParamSpec::number("conductivity", "W/(m*K)", 0.0, "thermal conductivity k (thermal cases)", 0.0),
          ParamSpec::number("specific_heat", "J/(kg*K)", 0.0,
                            "specific heat capacity c (thermal cases need it; 0: no thermal properties)", 0.0),
          j2::OptionalOutputs::spec(),
          j2::FailureCriterion::spec(),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
