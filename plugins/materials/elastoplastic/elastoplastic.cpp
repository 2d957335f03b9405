// Material plugin `elastoplastic`: isotropic linear elasticity with von Mises (J2) plasticity,
// perfectly plastic or with linear isotropic hardening, and a linear equation of state.
// docs/theory.md, eqs. 15-17.
#include <algorithm>
#include <cmath>

#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class Elastoplastic final : public Material {
 public:
  explicit Elastoplastic(const ParamValues& p)
      : rho0_(p.number("density")),
        E_(p.number("youngs_modulus")),
        nu_(p.number("poisson_ratio")),
        yield0_(p.number("yield_stress")),
        hardening_(p.number("hardening_modulus")),
        conductivity_(p.number("conductivity")),
        specific_heat_(p.number("specific_heat")) {
    G_ = E_ / (2.0 * (1.0 + nu_));
    K_ = E_ / (3.0 * (1.0 - 2.0 * nu_));
  }

  std::vector<FieldInfo> fields() const override {
    return {{field::plastic_strain, 1, "1"}, {field::von_mises_stress, 1, "Pa"}};
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
    double* eps_p = b.fields->f64(field::plastic_strain) + b.first;
    double* vm = b.fields->f64(field::von_mises_stress) + b.first;
    const double two_g_dt = 2.0 * G_ * b.dt;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < b.count; ++i) {
      const double* L = b.velocity_gradient + 9 * i;
      double* s = b.deviatoric_stress + 6 * i;
      // Elastic predictor with the deviatoric rate of deformation D' = sym(L) - tr(L)/3 I (eq. 15)
      const double tr3 = (L[0] + L[4] + L[8]) / 3.0;
      s[0] += two_g_dt * (L[0] - tr3);
      s[1] += two_g_dt * (L[4] - tr3);
      s[2] += two_g_dt * (L[8] - tr3);
      s[3] += two_g_dt * 0.5 * (L[1] + L[3]);
      s[4] += two_g_dt * 0.5 * (L[5] + L[7]);
      s[5] += two_g_dt * 0.5 * (L[2] + L[6]);
      // Radial return to the von Mises surface q = sigma_y0 + H eps_p (eq. 16); for linear
      // hardening the consistency condition is linear in d_eps_p, so the return is exact.
      const double ss = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
      const double q = std::sqrt(1.5 * ss);
      const double yield = yield0_ + hardening_ * eps_p[i];
      if (q > yield) {
        const double d_eps_p = (q - yield) / (3.0 * G_ + hardening_);
        const double scale = (yield + hardening_ * d_eps_p) / q;
        for (int c = 0; c < 6; ++c) s[c] *= scale;
        eps_p[i] += d_eps_p;
        vm[i] = yield + hardening_ * d_eps_p;
      } else {
        vm[i] = q;
      }
      // Linear equation of state (eq. 17)
      b.pressure[i] = K_ * (b.density[i] / rho0_ - 1.0);
    }
  }

  void yield_stress(const MaterialBatch& b, double* out) const override {
    const double* eps_p = b.fields->f64(field::plastic_strain) + b.first;
    for (std::size_t i = 0; i < b.count; ++i) out[i] = yield0_ + hardening_ * eps_p[i];
  }

 private:
  double rho0_, E_, nu_, yield0_, hardening_, conductivity_, specific_heat_, G_ = 0, K_ = 0;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Elastoplastic>(
      "elastoplastic", "0.1.0",
      "linear elasticity with von Mises plasticity, perfectly plastic or linear isotropic hardening",
      {
        ParamSpec::number("density", "kg/m^3", std::nullopt, "reference density rho0 (mass-scaled if wanted)", 1e-6),
        ParamSpec::number("youngs_modulus", "Pa", std::nullopt, "Young's modulus E", 1e-6),
        ParamSpec::number("poisson_ratio", "1", std::nullopt, "Poisson's ratio nu", -0.999, 0.4999),
        ParamSpec::number("yield_stress", "Pa", std::nullopt, "initial yield stress sigma_y0", 0.0),
        ParamSpec::number("hardening_modulus", "Pa", 0.0, "linear isotropic hardening modulus H (0: perfectly plastic)", 0.0),
        ParamSpec::number("conductivity", "W/(m*K)", 0.0, "thermal conductivity k (thermal cases)", 0.0),
        ParamSpec::number("specific_heat", "J/(kg*K)", 0.0,
                          "specific heat capacity c (thermal cases need it; 0: no thermal properties)", 0.0),
    });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
