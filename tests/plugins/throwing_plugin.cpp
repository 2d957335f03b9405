// A contact plugin whose constructor throws InputError itself (not through ParamValues::fail), as a
// plugin author may: the core must report it as an input error (exit 2), not crash
// (tests/integration/test_cli.cpp, CliInput.PluginThrowingInputError).
#include "sphforge/errors.hpp"
#include "sphforge/plugin.hpp"

namespace {
using namespace sphforge;
class Throwing final : public ContactLaw {
 public:
  explicit Throwing(const ParamValues& p) { throw InputError(p.file(), p.pointer_of("gain"), "gain refused by the plugin"); }
  void tangential_forces(ContactBatch&) const override {}
};
const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Throwing>(
      "test_throwing", "9.9.9", "test plugin that throws InputError", {ParamSpec::number("gain", "1", 1.0, "refused")});
  return d;
}
}  // namespace

SPHFORGE_PLUGIN(descriptor)
