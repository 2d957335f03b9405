// A minimal, valid contact plugin used by the loader tests.
#include "sphforge/plugin.hpp"

namespace {
using namespace sphforge;
class Frictionless final : public ContactLaw {
 public:
  explicit Frictionless(const ParamValues&) {}
  void tangential_forces(ContactBatch& b) const override {
    for (std::size_t c = 0; c < 3 * b.count; ++c) b.tangential_force[c] = 0.0;
  }
};
const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Frictionless>(
      "test_good", "9.9.9", "test plugin", {ParamSpec::number("gain", "1", 1.0, "unused")});
  return d;
}
}  // namespace

SPHFORGE_PLUGIN(descriptor)
