// Contact plugin `navier_slip`: a pressure-independent wall shear stress
// tau_w = tau_0 + beta V^n of the slip speed V = |v_t| (paste ram extrusion, docs/theory.md
// eq. 18g), acting on the particle's wall area A = dx^2 against v_t.
// Regularisation near V = 0 (eq. 18h): the force is never larger than the one that makes the
// particle move with the wall within the step, f_stick = -m (v_t/dt + a_t) (eq. 18a). Below the
// yield value tau_0 A the wall therefore holds the particle (a Bingham-like plug at rest), there is
// no division by V, and the step cannot reverse the slip direction, so the force does not chatter.
#include <cmath>

#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class NavierSlip final : public ContactLaw {
 public:
  explicit NavierSlip(const ParamValues& p)
      : tau0_(p.number("yield_shear_stress")),
        beta_(p.number("slip_coefficient")),
        n_(p.number("slip_exponent")),
        range_(p.number("wall_range")) {}

  // The wall shear does not depend on the pressure, so the wall-adjacent particles carry it also
  // where they do not press on the wall (eq. 18i).
  double wall_range() const override { return range_; }

  void tangential_forces(ContactBatch& b) const override {
    for (std::size_t c = 0; c < b.count; ++c) {
      const double* vt = b.tangential_velocity + 3 * c;
      double* ft = b.tangential_force + 3 * c;
      const double speed = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
      const double limit = (tau0_ + beta_ * std::pow(speed, n_)) * b.contact_area[c];
      double stick[3];
      const double stick_norm = sticking_force(b, c, stick);
      if (stick_norm <= limit) {
        for (int d = 0; d < 3; ++d) ft[d] = stick[d];
        b.sticking[c] = 1.0;
      } else {
        for (int d = 0; d < 3; ++d) ft[d] = speed > 0.0 ? -limit * vt[d] / speed : limit * stick[d] / stick_norm;
        b.sticking[c] = 0.0;
      }
    }
  }

 private:
  double tau0_, beta_, n_, range_;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<NavierSlip>(
      "navier_slip", "0.1.0",
      "Navier slip wall law tau_w = tau_0 + beta V^n, pressure independent, sticking below it",
      {ParamSpec::number("yield_shear_stress", "Pa", std::nullopt, "tau_0: wall shear stress at zero slip", 0.0),
       ParamSpec::number("slip_coefficient", "1", std::nullopt,
                         "beta in Pa (s/m)^n (SI number; its unit depends on n)", 0.0),
       ParamSpec::number("slip_exponent", "1", 1.0, "n", 0.0, 2.0),
       ParamSpec::number("wall_range", "1", 0.25,
                         "the law acts on particles closer than (1/2 + wall_range) dx to the wall, touching or "
                         "not (theory eq. 18i); below 1 so that only the wall-adjacent layer is reached",
                         0.0, 0.9)});
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
