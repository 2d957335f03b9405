// Controller plugin `pid`: drives one commanded quantity so that one measured signal follows a
// target, with output saturation and anti-windup (docs/theory.md eqs. 61-64; the law itself is in
// pid_law.hpp). Example, the friction-extrusion die (reference/friction_extrusion.md eqs. 13-16):
//   {"plugin": "pid", "name": "die_pid", "measured": "die_force_z", "command": "die_axial_velocity",
//    "target": "300 kN", "kp": "0.015 mm/s/kN", "ki": "0.02 mm/s/kN/s", "kd": "2e-5 mm/kN",
//    "command_limits": ["-0.04 mm/s", "0.4 mm/s"], "integral_limits": ["-0.01 mm/s", "0.4 mm/s"],
//    "sample_interval": "0.01 s"}
// The target is offered to other controllers as the command `<name>_target`, so a `schedule`
// (listed before the PID) can ramp it.
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pid_law.hpp"
#include "sphforge/errors.hpp"
#include "sphforge/plugin.hpp"

namespace {

using namespace sphforge;
using control::AntiWindup;
using control::DerivativeOn;

/// A unit expression as a history-column suffix: "m/s" -> "m_s", "N" -> "N", "kg*m^2" -> "kg_m2".
std::string column_unit(std::string unit) {
  std::string out;
  for (char c : unit) {
    if (c == '/' || c == '*' || c == ' ') out += '_';
    else if (c != '^' && c != '(' && c != ')') out += c;
  }
  return out;
}

class Pid final : public Controller {
 public:
  explicit Pid(const ParamValues& p) : params_(p), name_(p.string("name")) {}

  void declare(SignalBus& bus) override {
    measured_signal_ = &bus.require_measured(params_, "measured");
    target_ = params_.quantity("target", measured_signal_->unit);
    if (bus.command(name_ + "_target"))
      params_.fail("name", "another controller already offers the command '" + name_ + "_target': give each pid its own name");
    bus.add_command(name_ + "_target", measured_signal_->unit, &target_);
  }

  void bind(SignalBus& bus) override {
    const SignalBus::Signal& cmd = bus.require_command(params_, "command");
    if (params_.string("command") == name_ + "_target") params_.fail("command", "a PID cannot drive its own target");
    command_ = cmd.value;
    const std::string u = cmd.unit, y = measured_signal_->unit;

    // Gains carry units, e.g. "0.015 mm/s/kN": a gain meant for another command or signal is
    // refused here by its dimension, before the run.
    control::PidSettings s;
    s.kp = params_.quantity("kp", "(" + u + ")/(" + y + ")");
    s.ki = params_.quantity("ki", "(" + u + ")/(" + y + ")/s");
    s.kd = params_.quantity("kd", "(" + u + ")*s/(" + y + ")");
    if (!params_.raw("command_limits").empty()) {
      const auto lim = params_.quantities("command_limits", 2, u);
      if (!(lim[0] < lim[1])) params_.fail("command_limits", "expected [min, max] with min < max");
      s.command_min = lim[0];
      s.command_max = lim[1];
    }
    const std::string& aw = params_.string("anti_windup");
    s.anti_windup = aw == "none" ? AntiWindup::none
                    : aw == "conditional" ? AntiWindup::conditional
                    : aw == "back_calculation" ? AntiWindup::back_calculation
                                               : AntiWindup::clamp;
    if (!params_.raw("integral_limits").empty()) {
      if (s.anti_windup != AntiWindup::clamp)
        params_.fail("integral_limits", "integral limits belong to anti_windup \"clamp\" (this PID uses \"" + aw + "\")");
      const auto lim = params_.quantities("integral_limits", 2, u);
      if (!(lim[0] < lim[1])) params_.fail("integral_limits", "expected [min, max] with min < max");
      s.integral_min = lim[0];
      s.integral_max = lim[1];
    } else {
      // Default clamp: the integral alone never asks for more than the actuator can give.
      s.integral_min = s.command_min;
      s.integral_max = s.command_max;
    }
    if (s.anti_windup == AntiWindup::back_calculation) {
      if (s.ki == 0.0) params_.fail("anti_windup", "back_calculation needs ki > 0");
      s.tracking_time = params_.number("tracking_time");
      // Default Tt = Ti = Kp/Ki (a common choice, Astrom & Hagglund), or 1 s for a pure I law.
      if (!(s.tracking_time > 0.0)) s.tracking_time = s.kp > 0.0 ? s.kp / s.ki : 1.0;
    }
    s.derivative_on = params_.string("derivative_on") == "measurement" ? DerivativeOn::measurement : DerivativeOn::error;
    s.sample_interval = params_.number("sample_interval");
    law_.emplace(s);

    const std::string cu = column_unit(u), yu = column_unit(y);
    columns_ = {{name_ + "_target_" + yu, &target_},
                {name_ + "_error_" + yu, &terms_.error},
                {name_ + "_p_" + cu, &terms_.proportional},
                {name_ + "_i_" + cu, &terms_.integral},
                {name_ + "_d_" + cu, &terms_.derivative},
                {name_ + "_command_" + cu, &terms_.command},
                {name_ + "_reversals_1", &reversals_}};
  }

  void update(double time_s, double) override {
    if (law_->update(time_s, target_, *measured_signal_->value)) {
      terms_ = law_->terms();
      reversals_ = static_cast<double>(law_->reversals());
    }
    *command_ = terms_.command;  // held between samples
  }

  std::vector<HistoryColumn> history_columns() const override { return columns_; }

  // Restart: the law's memory (integral, last sample) and the terms of the last sample, which the
  // command is held at. The target is a signal of the bus (`<name>_target`), saved by the core.
  bool supports_restart() const override { return true; }
  nlohmann::json save_state() const override {
    const control::PidLaw::Memory m = law_->memory();
    auto terms = [](const control::PidTerms& t) {
      return nlohmann::json::array({t.error, t.proportional, t.integral, t.derivative, t.command});
    };
    return {{"law_terms", terms(m.terms)},       {"sampled", m.sampled},
            {"integral", m.integral},            {"last_error", m.last_error},
            {"last_measured", m.last_measured},  {"last_time", m.last_time},
            {"next_sample", m.next_sample},      {"saturation_excess", m.saturation_excess},
            {"last_change", m.last_change},      {"reversals", m.reversals},
            {"held_terms", terms(terms_)}};
  }
  void restore_state(const nlohmann::json& s) override {
    auto terms = [](const nlohmann::json& a) {
      return control::PidTerms{a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>(),
                               a.at(3).get<double>(), a.at(4).get<double>()};
    };
    control::PidLaw::Memory m;
    m.terms = terms(s.at("law_terms"));
    m.sampled = s.at("sampled").get<bool>();
    m.integral = s.at("integral").get<double>();
    m.last_error = s.at("last_error").get<double>();
    m.last_measured = s.at("last_measured").get<double>();
    m.last_time = s.at("last_time").get<double>();
    m.next_sample = s.at("next_sample").get<double>();
    m.saturation_excess = s.at("saturation_excess").get<double>();
    // Absent from checkpoints written before the diagnostic existed: the count restarts from 0.
    m.last_change = s.value("last_change", 0.0);
    m.reversals = s.value("reversals", 0L);
    law_->restore(m);
    terms_ = terms(s.at("held_terms"));
    reversals_ = static_cast<double>(m.reversals);
  }

 private:
  ParamValues params_;
  std::string name_;
  const SignalBus::Signal* measured_signal_ = nullptr;
  double* command_ = nullptr;
  double target_ = 0.0;
  std::optional<control::PidLaw> law_;
  control::PidTerms terms_;
  double reversals_ = 0.0;  ///< law_->reversals() of the last sample, as a history column
  std::vector<HistoryColumn> columns_;
};

const PluginDescriptor& descriptor() {
  static const PluginDescriptor d = make_plugin_descriptor<Pid>(
      "pid", "0.2.0",
      "PID control of a commanded quantity from a measured signal, sampled, saturated, with anti-windup",
      {
          ParamSpec::string("name", "pid", "prefix of its history columns and of its target command <name>_target"),
          ParamSpec::string("measured", std::nullopt, "measured signal, e.g. die_force_z (see the process)"),
          ParamSpec::string("command", std::nullopt, "commanded quantity, e.g. die_axial_velocity"),
          ParamSpec::quantity("target", "set point in the measured signal's unit, e.g. \"300 kN\""),
          ParamSpec::quantity("kp", "proportional gain, command unit per measured unit, e.g. \"0.015 mm/s/kN\""),
          ParamSpec::quantity("ki", "integral gain, command unit per (measured unit s), e.g. \"0.02 mm/s/kN/s\""),
          ParamSpec::quantity("kd", "derivative gain, command unit s per measured unit, e.g. \"2e-5 mm/kN\""),
          ParamSpec::array("command_limits", "[min, max] of the command (saturation), e.g. [\"-0.04 mm/s\", \"0.4 mm/s\"]"),
          ParamSpec::string("anti_windup", "clamp", "clamp (paper eq. 16), conditional (freeze while saturated), "
                            "back_calculation or none", {"clamp", "conditional", "back_calculation", "none"}),
          ParamSpec::array("integral_limits", "[min, max] of the integral contribution Ki I in command units "
                           "(anti_windup clamp; default: command_limits)"),
          ParamSpec::number("tracking_time", "s", 0.0, "Tt of back-calculation; 0: Kp/Ki", 0.0),
          ParamSpec::string("derivative_on", "error", "error (as the paper) or measurement (no kick on target steps)",
                            {"error", "measurement"}),
          ParamSpec::number("sample_interval", "s", 0.0, "sampling interval dt_pid; 0: every time step", 0.0),
      });
  return d;
}

}  // namespace

SPHFORGE_PLUGIN(descriptor)
