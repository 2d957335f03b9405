#include "engine/controller_phases.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "sphforge/errors.hpp"
#include "sphforge/units.hpp"

namespace sphforge {

namespace {

const ParamSpecs& phase_specs() {
  static const ParamSpecs specs = {
      ParamSpec::string("name", std::nullopt, "phase name (summary.json)"),
      ParamSpec::array("controllers", "controller plugins active during this phase"),
      ParamSpec::object("end", "end condition; absent only for the last phase (then it lasts to run.end_time)"),
  };
  return specs;
}

const ParamSpecs& end_specs() {
  static const ParamSpecs specs = {
      ParamSpec::number("duration", "s", 0.0, "the phase ends after this time (0: no time limit)", 0.0),
      ParamSpec::string("signal", std::string(), "measured signal of the condition, e.g. ram_displacement"),
      ParamSpec::string("above", std::string(), "ends when the signal exceeds this value, e.g. \"5 mm\""),
      ParamSpec::string("below", std::string(), "ends when the signal falls below this value"),
  };
  return specs;
}

}  // namespace

bool ControllerPhases::Phase::ended(double time) const {
  // Eq. 65: a relative slack of 1e-12 keeps accumulated step times from missing the instant.
  if (time - start >= duration * (1.0 - 1e-12)) return true;
  return signal != nullptr && (*signal > above || *signal < below);
}

void ControllerPhases::load(const ParamValues& root, const MakeController& make, SignalBus& bus) {
  const json& list = root.raw("controllers");
  for (std::size_t k = 0; k < list.size(); ++k) {
    run_long_pointers_.push_back("/controllers/" + std::to_string(k));
    run_long_.push_back(make(list[k], run_long_pointers_.back()));
  }

  const json& phases = root.raw("phases");
  for (std::size_t p = 0; p < phases.size(); ++p) {
    const ParamValues ph = root.element("phases", p, phase_specs());
    Phase phase;
    phase.name = ph.string("name");
    const json& controllers = ph.raw("controllers");
    for (std::size_t k = 0; k < controllers.size(); ++k) {
      phase.pointers.push_back(ph.pointer() + "/controllers/" + std::to_string(k));
      phase.controllers.push_back(make(controllers[k], phase.pointers.back()));
    }
    if (ph.has("end") && !ph.raw("end").empty()) {
      const ParamValues end = ph.sub("end", end_specs());
      if (end.number("duration") > 0.0) phase.duration = end.number("duration");
      const std::string& name = end.string("signal");
      const bool threshold = !end.string("above").empty() || !end.string("below").empty();
      if (!name.empty()) {
        const SignalBus::Signal* s = &bus.require_measured(end, "signal");
        if (!threshold) end.fail("signal", "a signal condition needs \"above\" or \"below\"");
        phase.signal = s->value;
        for (const char* key : {"above", "below"}) {
          const std::string& text = end.string(key);
          if (text.empty()) continue;
          try {
            (key[0] == 'a' ? phase.above : phase.below) = parse_quantity(text, s->unit);
          } catch (const std::exception& e) {
            end.fail(key, e.what());
          }
        }
      } else if (threshold) {
        end.fail("signal", "\"above\"/\"below\" need the measured \"signal\" they refer to");
      }
      if (!phase.has_end()) end.fail("", "expected a \"duration\" and/or a \"signal\" with \"above\"/\"below\"");
    } else if (p + 1 < phases.size()) {
      ph.fail("end", "missing: only the last phase may run without an end condition");
    }
    phases_.push_back(std::move(phase));
  }
  if (!phases_.empty()) {
    phases_[0].start = 0.0;
    phase_number_ = 1.0;
  }

  // Two passes (Controller::declare), so that a controller may drive a command another one offers
  // (a schedule driving a PID's target) wherever either stands; updates follow the list order.
  auto each = [&](const std::function<void(Controller&)>& f) {
    for (auto& c : run_long_) f(*c);
    for (auto& ph : phases_)
      for (auto& c : ph.controllers) f(*c);
  };
  each([&](Controller& c) { c.declare(bus); });
  each([&](Controller& c) { c.bind(bus); });
}

void ControllerPhases::update(double time, double dt) {
  if (!phases_.empty() && !finished_ && phases_[current_].has_end() && phases_[current_].ended(time)) {
    phases_[current_].end = time;
    if (current_ + 1 < phases_.size()) {
      ++current_;
      phases_[current_].start = time;
      phase_number_ = static_cast<double>(current_ + 1);
    } else {
      finished_ = true;
    }
  }
  for (auto& c : run_long_) c->update(time, dt);
  if (!phases_.empty() && !finished_)
    for (auto& c : phases_[current_].controllers) c->update(time - phases_[current_].start, dt);
}

std::vector<HistoryColumn> ControllerPhases::history_columns() const {
  std::vector<HistoryColumn> columns;
  if (!phases_.empty()) columns.push_back({"phase_1", &phase_number_});
  for (const auto& c : run_long_)
    for (const auto& col : c->history_columns()) columns.push_back(col);
  for (const auto& ph : phases_)
    for (const auto& c : ph.controllers)
      for (const auto& col : c->history_columns()) columns.push_back(col);
  return columns;
}

json ControllerPhases::summary() const {
  json list = json::array();
  for (const auto& ph : phases_) {
    json p = {{"name", ph.name}};
    p["start_s"] = std::isnan(ph.start) ? json(nullptr) : json(ph.start);
    p["end_s"] = std::isnan(ph.end) ? json(nullptr) : json(ph.end);
    list.push_back(p);
  }
  return list;
}

std::string ControllerPhases::first_without_restart() const {
  for (std::size_t k = 0; k < run_long_.size(); ++k)
    if (!run_long_[k]->supports_restart()) return run_long_pointers_[k];
  for (const auto& ph : phases_)
    for (std::size_t k = 0; k < ph.controllers.size(); ++k)
      if (!ph.controllers[k]->supports_restart()) return ph.pointers[k];
  return {};
}

namespace {
// JSON has no NaN: a phase that has not started or ended is saved as null.
json time_or_null(double t) { return std::isnan(t) ? json(nullptr) : json(t); }
double time_from(const json& j) { return j.is_null() ? std::numeric_limits<double>::quiet_NaN() : j.get<double>(); }
}  // namespace

json ControllerPhases::save_state() const {
  json run_long = json::array();
  for (const auto& c : run_long_) run_long.push_back(c->save_state());
  json phases = json::array();
  for (const auto& ph : phases_) {
    json controllers = json::array();
    for (const auto& c : ph.controllers) controllers.push_back(c->save_state());
    phases.push_back({{"start", time_or_null(ph.start)}, {"end", time_or_null(ph.end)}, {"controllers", controllers}});
  }
  return {{"current", current_}, {"finished", finished_}, {"run_long", run_long}, {"phases", phases}};
}

void ControllerPhases::restore_state(const json& state) {
  const json& run_long = state.at("run_long");
  const json& phases = state.at("phases");
  if (run_long.size() != run_long_.size() || phases.size() != phases_.size())
    throw std::runtime_error("the checkpoint holds " + std::to_string(run_long.size()) + " controllers and " +
                             std::to_string(phases.size()) + " phases, the case " + std::to_string(run_long_.size()) +
                             " and " + std::to_string(phases_.size()));
  for (std::size_t k = 0; k < run_long_.size(); ++k) run_long_[k]->restore_state(run_long[k]);
  for (std::size_t p = 0; p < phases_.size(); ++p) {
    Phase& ph = phases_[p];
    const json& saved = phases[p];
    if (saved.at("controllers").size() != ph.controllers.size())
      throw std::runtime_error("phase '" + ph.name + "' has another number of controllers in the checkpoint");
    ph.start = time_from(saved.at("start"));
    ph.end = time_from(saved.at("end"));
    for (std::size_t k = 0; k < ph.controllers.size(); ++k) ph.controllers[k]->restore_state(saved.at("controllers")[k]);
  }
  current_ = state.at("current").get<std::size_t>();
  finished_ = state.at("finished").get<bool>();
  phase_number_ = phases_.empty() ? 0.0 : static_cast<double>(current_ + 1);
}

}  // namespace sphforge
