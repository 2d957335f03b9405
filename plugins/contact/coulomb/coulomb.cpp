// Contact plugin `coulomb`: Coulomb friction |f_t| <= mu f_n (docs/theory.md, eq. 18).
// The sticking trial force is the force that cancels the relative tangential velocity within
// the step, f_trial = -m v_t / dt; if it lies inside the cone the particle sticks, otherwise it
// slides with |f_t| = mu f_n opposite to v_t.
#include <cmath>

#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class Coulomb final : public ContactLaw {
 public:
  explicit Coulomb(const ParamValues& p) : mu_(p.number("friction_coefficient")) {}

  void tangential_forces(ContactBatch& b) const override {
    for (std::size_t c = 0; c < b.count; ++c) {
      const double* vt = b.tangential_velocity + 3 * c;
      double* ft = b.tangential_force + 3 * c;
      const double k = -b.mass[c] / b.dt;
      const double trial[3] = {k * vt[0], k * vt[1], k * vt[2]};
      const double trial_norm = std::sqrt(trial[0] * trial[0] + trial[1] * trial[1] + trial[2] * trial[2]);
      const double limit = mu_ * b.normal_force[c];
      if (trial_norm <= limit) {
        for (int d = 0; d < 3; ++d) ft[d] = trial[d];
        b.sticking[c] = 1.0;
      } else {
        const double scale = limit / trial_norm;
        for (int d = 0; d < 3; ++d) ft[d] = trial[d] * scale;
        b.sticking[c] = 0.0;
      }
    }
  }

 private:
  double mu_;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Coulomb>(
      "coulomb", "0.1.0",
      "Coulomb friction, tangential force limited by mu times the normal force, with sticking",
      {ParamSpec::number("friction_coefficient", "1", std::nullopt, "Coulomb coefficient mu", 0.0, 10.0)});
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
