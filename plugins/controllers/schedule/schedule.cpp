// Controller plugin `schedule`: a commanded quantity as a piecewise-linear function of time
// (docs/theory.md eq. 60), e.g. the friction-extrusion experiment's rotation speed
//   {"plugin": "schedule", "command": "die_angular_velocity",
//    "points": [["0 s", "300 rpm"], ["26 s", "300 rpm"], ["36 s", "90 rpm"]]}
// or a PID's target (the command `<pid name>_target`): 50 kN while heating, ramped to 300 kN.
#include <string>

#include "sphforge/errors.hpp"
#include "sphforge/piecewise_linear.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;

class Schedule final : public Controller {
 public:
  explicit Schedule(const ParamValues& p) : params_(p) {}

  void bind(SignalBus& bus) override {
    const SignalBus::Signal* signal = &bus.require_command(params_, "command");
    function_ = PiecewiseLinear(params_.pairs("points", "s", signal->unit));
    target_ = signal->value;
    *target_ = function_(0.0);
  }

  void update(double time_s, double) override { *target_ = function_(time_s); }
  /// Restart: a function of time only, nothing to save.
  bool supports_restart() const override { return true; }

 private:
  ParamValues params_;
  PiecewiseLinear function_;
  double* target_ = nullptr;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Schedule>(
      "schedule", "0.1.0",
      "a commanded quantity (or a PID's target) as a piecewise-linear function of time",
      {
          ParamSpec::string("command", std::nullopt, "commanded quantity, e.g. ram_velocity or die_pid_target"),
          ParamSpec::array("points", "[[time, value], ...] with units, e.g. [[\"0 s\", \"0 mm/s\"], [\"1 s\", \"1 mm/s\"]]; "
                           "held constant before the first and after the last point", true),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
