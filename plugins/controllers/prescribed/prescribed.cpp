// Controller plugin `prescribed`: holds one commanded quantity at a constant value, e.g. the
// ram velocity of a ram-extrusion process.
#include "sphforge/errors.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class Prescribed final : public Controller {
 public:
  explicit Prescribed(const ParamValues& p) : params_(p) {}

  void bind(SignalBus& bus) override {
    const SignalBus::Signal* signal = &bus.require_command(params_, "command");
    // The value's unit is that of the command, known only now.
    value_ = params_.quantity("value", signal->unit);
    target_ = signal->value;
    *target_ = value_;
  }

  void update(double, double) override { *target_ = value_; }
  /// Restart: a function of time only, nothing to save.
  bool supports_restart() const override { return true; }

 private:
  ParamValues params_;
  double* target_ = nullptr;
  double value_ = 0.0;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Prescribed>(
      "prescribed", "0.1.0",
      "holds a commanded quantity (e.g. ram_velocity) at a constant value",
      {
        ParamSpec::string("command", std::nullopt, "name of the commanded quantity (see the process)"),
        ParamSpec::quantity("value", "value in the command's unit, e.g. \"1 mm/s\" for ram_velocity"),
    });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
