// Contact plugin `coulomb_tresca`: f_t = min(mu |f_n|, sigma_y A / sqrt(3)) against the relative
// tangential velocity (docs/theory.md eq. 18d; friction-extrusion paper, eqs. 4-5), A = dx^2 and
// sigma_y the workpiece material's current yield stress.
// - Coulomb regime (mu f_n <= tau_y A): the particle slides with mu f_n, or sticks when the force
//   that makes it move with the wall, f_stick = -m (v_t/dt + a_t) (eq. 18a), lies inside the cone.
// - Sticking regime (mu f_n > tau_y A): the particle moves with the wall (v = v_wall); the force
//   that holds it is f_stick, but never more than the shear strength tau_y A of the particle's
//   contact area: beyond it the material at the wall shears at its yield stress (Tresca friction
//   factor 1), which is the min() of the law.
// - With `sticking: "kinematic"` (the friction-extrusion paper's rule, eq. 18j) a contact in the
//   sticking regime is held on the wall by f_stick whatever its size, and makes no friction heat.
//   Under mass scaling f_stick carries the scaled inertia of the particle, so the default limit
//   tau_y A lets the wall layer slide where the paper's particles stick.
#include <cmath>

#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class CoulombTresca final : public ContactLaw {
 public:
  explicit CoulombTresca(const ParamValues& p)
      : mu_(p.number("friction_coefficient")), kinematic_(p.string("sticking") == "kinematic") {}

  bool needs_yield_stress() const override { return true; }

  void tangential_forces(ContactBatch& b) const override {
    const double inv_sqrt3 = 1.0 / std::sqrt(3.0);
    for (std::size_t c = 0; c < b.count; ++c) {
      const double* vt = b.tangential_velocity + 3 * c;
      double* ft = b.tangential_force + 3 * c;
      const double coulomb = mu_ * b.normal_force[c];
      const double tresca = b.yield_stress[c] * inv_sqrt3 * b.contact_area[c];
      double stick[3];
      const double stick_norm = sticking_force(b, c, stick);
      const bool tresca_regime = coulomb > tresca;
      const double limit = tresca_regime ? tresca : coulomb;
      if (tresca_regime && kinematic_) {
        for (int d = 0; d < 3; ++d) ft[d] = stick[d];
        b.sticking[c] = kHeldOnWall;
        continue;
      }
      if (stick_norm <= limit) {
        for (int d = 0; d < 3; ++d) ft[d] = stick[d];
      } else {
        // Against v_t (eq. 18d); when v_t vanishes the sticking force gives the direction.
        const double speed = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
        for (int d = 0; d < 3; ++d) ft[d] = speed > 0.0 ? -limit * vt[d] / speed : limit * stick[d] / stick_norm;
      }
      b.sticking[c] = (tresca_regime || stick_norm <= limit) ? 1.0 : 0.0;
    }
  }

 private:
  double mu_;
  bool kinematic_;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<CoulombTresca>(
      "coulomb_tresca", "0.1.0",
      "Coulomb friction capped by the Tresca shear limit sigma_y A / sqrt(3); full sticking beyond it",
      {ParamSpec::number("friction_coefficient", "1", std::nullopt, "Coulomb coefficient mu", 0.0, 10.0),
       ParamSpec::string("sticking", "force_limited",
                         "sticking regime (mu f_n > tau_y A): force_limited (held by at most tau_y A, eq. 18d) or "
                         "kinematic (held on the wall whatever the force, no friction heat: the friction-extrusion "
                         "paper's rule, eq. 18j)",
                         {"force_limited", "kinematic"})});
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
