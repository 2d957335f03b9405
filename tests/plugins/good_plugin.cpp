// A minimal, valid contact plugin used by the loader tests.
#include "sphforge/plugin.hpp"

namespace {
using namespace sphforge;
class Frictionless final : public ContactLaw {
 public:
  void tangential_forces(ContactBatch& b) const override {
    for (std::size_t c = 0; c < 3 * b.count; ++c) b.tangential_force[c] = 0.0;
  }
};
const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = [] {
    PluginDescriptor p;
    p.kind = PluginKind::Contact;
    p.name = "test_good";
    p.version = "9.9.9";
    p.doc = "test plugin";
    p.parameters = {ParamSpec::number("gain", "1", 1.0, "unused")};
    p.make_contact = [](const ParamValues&) { return std::make_unique<Frictionless>(); };
    return p;
  }();
  return d;
}
}  // namespace

SPHFORGE_PLUGIN(descriptor)
