// Contact plugin `coulomb`: Coulomb friction |f_t| <= mu f_n with sticking represented by an
// elastic trial force, as explicit finite-element codes do (docs/theory.md eqs. 18, 18b-18c).
// The trial (stick) force is f* = -m a_t + s* - c_t v_t: it balances the particle's other
// tangential forces (a_t, eq. 18a), plus a tangential spring s* = P s - k_t dt v_t (P: projection
// on the current tangent plane) that accumulates the relative tangential motion while the contact
// sticks, and a dashpot c_t. Inside the cone |f*| <= mu f_n the contact sticks (f_t = f*, s = s*);
// outside, it returns to the cone, f_t = mu f_n f*/|f*|, and the spring keeps the value that
// reproduces that force, s = f_t + m a_t + c_t v_t. A stuck particle is held against any tangential
// load below mu f_n; its residual motion is a damped oscillation of the spring (amplitude |s|/k_t).
#include <cmath>

#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class Coulomb final : public ContactLaw {
 public:
  explicit Coulomb(const ParamValues& p)
      : mu_(p.number("friction_coefficient")),
        stiffness_factor_(p.number("tangential_stiffness_factor")),
        damping_ratio_(p.number("tangential_damping_ratio")) {}

  bool needs_history() const override { return true; }

  void tangential_forces(ContactBatch& b) const override {
    // k_t <= k keeps the tangential oscillator inside the normal contact's stability limit
    // (eq. 12), which already sets the time step.
    const double kt = stiffness_factor_ * b.stiffness;
    for (std::size_t c = 0; c < b.count; ++c) {
      const double* n = b.normal + 3 * c;
      const double* vt = b.tangential_velocity + 3 * c;
      const double* acc = b.acceleration + 3 * c;
      double* ft = b.tangential_force + 3 * c;
      double* hs = b.history + 3 * c;
      const double m = b.mass[c];
      const double ct = 2.0 * damping_ratio_ * std::sqrt(kt * m);
      // The spring of the last step, projected on the current tangent plane (eq. 18b), and the
      // tangential part of the other forces' acceleration (eq. 18a).
      const double hn = hs[0] * n[0] + hs[1] * n[1] + hs[2] * n[2];
      const double an = acc[0] * n[0] + acc[1] * n[1] + acc[2] * n[2];
      double spring[3], trial[3], at[3];
      for (int d = 0; d < 3; ++d) {
        at[d] = acc[d] - an * n[d];
        spring[d] = hs[d] - hn * n[d] - kt * b.dt * vt[d];
        trial[d] = -m * at[d] + spring[d] - ct * vt[d];
      }
      const double trial_norm = std::sqrt(trial[0] * trial[0] + trial[1] * trial[1] + trial[2] * trial[2]);
      const double limit = mu_ * b.normal_force[c];
      if (trial_norm <= limit) {  // inside the cone: stick (eq. 18c)
        for (int d = 0; d < 3; ++d) {
          ft[d] = trial[d];
          hs[d] = spring[d];
        }
        b.sticking[c] = 1.0;
      } else {  // return to the cone: slide with mu f_n (eq. 18)
        const double scale = limit / trial_norm;
        for (int d = 0; d < 3; ++d) {
          ft[d] = trial[d] * scale;
          hs[d] = ft[d] + m * at[d] + ct * vt[d];
        }
        b.sticking[c] = 0.0;
      }
    }
  }

 private:
  double mu_, stiffness_factor_, damping_ratio_;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Coulomb>(
      "coulomb", "0.2.0",
      "Coulomb friction, tangential force limited by mu times the normal force; sticking by an elastic "
      "tangential spring (trial force returned to the cone)",
      {ParamSpec::number("friction_coefficient", "1", std::nullopt, "Coulomb coefficient mu", 0.0, 10.0),
       ParamSpec::number("tangential_stiffness_factor", "1", 1.0,
                         "tangential spring k_t as a fraction of the normal penalty stiffness k (eq. 18b)", 1e-6, 1.0),
       ParamSpec::number("tangential_damping_ratio", "1", 0.2,
                         "fraction of critical damping of the tangential spring (eq. 18b)", 0.0, 1.0)});
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
