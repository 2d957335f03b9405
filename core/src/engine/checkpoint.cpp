// Restart checkpoints (DESIGN.md "Outputs": checkpoint_NNNNNN.h5, `sphforge run CASE --restart
// FILE`; docs/checkpoints.md). A checkpoint holds every allocated particle field at full precision
// (io/particle_dump.hpp) and, as JSON text, what else the next step starts from: time, step, the
// core's energy ledgers, the tools' kinematics and reactions, every signal of the bus, the
// friction laws' memory, the process's and the controllers' own state and where the run loop
// stands (next frame, history row, checkpoint). A restart rebuilds the scene from the case as a new
// run would, then overwrites it with all of that; with the same number of threads the restarted
// run repeats the uninterrupted one step for step (tests/integration/test_checkpoint_restart.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "engine/simulation.hpp"
#include "io/particle_dump.hpp"
#include "sphforge/errors.hpp"
#include "sphforge/version.hpp"

namespace sphforge {

namespace fs = std::filesystem;

namespace {

// JSON has no infinities or NaN (a scene without tools has an infinite contact time step):
// those are stored as the strings "inf", "-inf" and "nan".
json number(double v) {
  if (std::isfinite(v)) return v;
  if (std::isnan(v)) return "nan";
  return v > 0 ? "inf" : "-inf";
}
double number(const json& j) {
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    return std::numeric_limits<double>::quiet_NaN();
  }
  return j.get<double>();
}

/// The case without its "run" section, which a restart may change (end time, intervals, threads).
json without_run(json root) {
  if (root.is_object()) root.erase("run");
  return root;
}

// Arrays the thermal pass keeps from one step to the next: the time step of a step is limited by
// the properties the previous step's thermal pass evaluated (eq. 26), not by those of the new
// temperatures.
constexpr const char* kConductivity = "restart_thermal_conductivity";
constexpr const char* kSpecificHeat = "restart_specific_heat";

}  // namespace

std::string Simulation::first_without_restart() const {
  if (!process_->supports_restart()) return "process '" + process_name_ + "'";
  if (const std::string pointer = controllers_.first_without_restart(); !pointer.empty())
    return "the controller at " + pointer;
  return {};
}

json Simulation::checkpoint_state(double wall_time_s) const {
  json core;
  core["time_s"] = time_;
  core["step"] = step_;
  core["dt_s"] = number(dt_);
  core["dt_initial_s"] = number(dt_initial_);
  core["dt_cfl_s"] = number(dt_cfl_);
  core["dt_contact_s"] = number(dt_contact_);
  core["dt_thermal_s"] = number(dt_thermal_);
  core["thermal_pending_s"] = thermal_pending_s_;  // eq. 26b; its heat is in the pending fields
  core["internal_energy_J"] = internal_energy_;
  core["constraint_work_J"] = constraint_work_J_;
  core["body_force_work_J"] = body_force_work_J_;
  core["initial_kinetic_energy_J"] = initial_kinetic_energy_;
  core["contact_time_s"] = contact_time_s_;
  core["contacts"] = contacts_;
  core["neighbour_builds"] = neighbours_.builds();
  core["tool_friction_heat_J"] = tool_friction_heat_J_;
  core["tool_heat_to_tool_J"] = tool_heat_to_tool_J_;
  long long failed_returns = failed_returns_before_restart_;
  for (const auto& material : materials_) failed_returns += material->failed_returns();
  core["material_failed_returns"] = failed_returns;
  core["wall_time_s"] = wall_time_s;

  json tools = json::array();
  for (const RigidTool& t : tools_)
    tools.push_back({{"name", t.name()},
                     {"axial_offset_m", t.axial_offset_m},
                     {"axial_velocity_m_s", t.axial_velocity_m_s},
                     {"angle_rad", t.angle_rad},
                     {"angular_velocity_rad_s", t.angular_velocity_rad_s},
                     {"reaction_force_N", {t.reaction_force_N.x(), t.reaction_force_N.y(), t.reaction_force_N.z()}},
                     {"reaction_torque_Nm", t.reaction_torque_Nm},
                     {"power_W", t.power_W},
                     {"friction_heat_W", t.friction_heat_W},
                     {"work_J", t.work_J}});

  // Every signal: the measured ones are the process's last measurement (which the controllers read
  // at the next step), the commands what the controllers hold.
  json measured = json::object(), commands = json::object();
  for (const std::string& name : signals_.measured_names()) measured[name] = number(*signals_.measured(name)->value);
  for (const std::string& name : signals_.command_names()) commands[name] = number(*signals_.command(name)->value);

  json friction = json::array();
  for (std::size_t t = 0; t < contact_.history_tools(); ++t) {
    json entries = json::array();
    for (const FrictionHistoryEntry& e : contact_.friction_history(t))
      entries.push_back({e.id, e.value[0], e.value[1], e.value[2]});
    friction.push_back(entries);
  }

  json cursor = {{"frame", cursor_.frame},
                 {"checkpoint", cursor_.checkpoint},
                 {"next_output_s", cursor_.next_output},
                 {"next_history_s", cursor_.next_history},
                 {"next_checkpoint_s", cursor_.next_checkpoint},
                 {"output_interval_s", settings_.output_interval_s},
                 {"history_interval_s", settings_.history_interval_s},
                 {"checkpoint_interval_s", settings_.checkpoint_interval_s},
                 {"max_kinetic_to_work", cursor_.max_kinetic_to_work}};

  return {{"core_version", kCoreVersion},
          {"case_file", case_file_},
          {"case", case_root_},
          {"core", core},
          {"tools", tools},
          {"signals", {{"measured", measured}, {"commands", commands}}},
          {"friction_history", friction},
          {"cursor", cursor},
          {"process", process_->save_state()},
          {"controllers", controllers_.save_state()}};
}

void Simulation::write_checkpoint(const fs::path& out_dir, double wall_time_s) {
  char name[32];
  std::snprintf(name, sizeof name, "checkpoint_%06d.h5", cursor_.checkpoint);
  ++cursor_.checkpoint;  // saved already advanced: a restart writes the next number
  std::vector<io::ParticleArray> extra;
  if (settings_.thermal.enabled) {
    // The real particles' values (with symmetry the conductivity array goes on with the ghosts').
    const auto real = [&](const std::vector<double>& a) {
      return std::vector<double>(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(count_));
    };
    extra.push_back({kConductivity, 1, "W/(m*K)", real(conductivity_)});
    extra.push_back({kSpecificHeat, 1, "J/(kg*K)", real(specific_heat_)});
  }
  io::write_checkpoint(out_dir / name, fields_, count_, time_, step_, checkpoint_state(wall_time_s).dump(), extra);
  // The run that writes the checkpoint rebuilds its lists at the next step, as a run restarted
  // from it must (it has none): both then build the same lists from the same positions.
  neighbours_.mark_stale();
  thermal_lists_stale_ = true;
}

void Simulation::restore(const fs::path& checkpoint) {
  const std::string file = checkpoint.string();
  if (const std::string missing = first_without_restart(); !missing.empty())
    throw InputError(case_file_, "", "cannot restart: " + missing +
                                         " keeps no restart state (supports_restart() is false); docs/checkpoints.md");
  // The rebuilt scene is initialised as a new run's (the process's initialize(), the domain a
  // particle may not leave, which is the initial scene's), then overwritten.
  prepare_run();
  std::vector<io::ParticleArray> extra;
  if (settings_.thermal.enabled) extra = {{kConductivity, 1, "W/(m*K)", {}}, {kSpecificHeat, 1, "J/(kg*K)", {}}};
  json state;
  try {
    state = json::parse(io::read_checkpoint(checkpoint, fields_, count_, extra));
  } catch (const std::exception& e) {
    throw InputError(file, "", std::string("cannot restart from this file: ") + e.what());
  }
  // Only the "run" section may differ: anything else would continue another scene's state.
  const json patch = json::diff(without_run(state.at("case")), without_run(case_root_));
  if (!patch.empty()) {
    const std::string pointer = patch.front().value("path", std::string());
    throw InputError(case_file_, pointer,
                     "differs from the case that wrote " + file + " (written from '" +
                         state.value("case_file", std::string("?")) + "'); a restart may change only \"run\"");
  }
  try {
    const json& core = state.at("core");
    time_ = core.at("time_s").get<double>();
    step_ = core.at("step").get<long long>();
    dt_ = number(core.at("dt_s"));
    dt_initial_ = number(core.at("dt_initial_s"));
    dt_cfl_ = number(core.at("dt_cfl_s"));
    dt_contact_ = number(core.at("dt_contact_s"));
    dt_thermal_ = number(core.at("dt_thermal_s"));
    thermal_pending_s_ = core.value("thermal_pending_s", 0.0);  // absent before eq. 26b: nothing pending
    internal_energy_ = core.at("internal_energy_J").get<double>();
    constraint_work_J_ = core.at("constraint_work_J").get<double>();
    body_force_work_J_ = core.at("body_force_work_J").get<double>();
    initial_kinetic_energy_ = core.at("initial_kinetic_energy_J").get<double>();
    contact_time_s_ = core.at("contact_time_s").get<double>();
    contacts_ = core.at("contacts").get<std::size_t>();
    neighbours_.continue_count(core.at("neighbour_builds").get<long long>());
    tool_friction_heat_J_ = core.at("tool_friction_heat_J").get<std::vector<double>>();
    tool_heat_to_tool_J_ = core.at("tool_heat_to_tool_J").get<std::vector<double>>();
    failed_returns_before_restart_ = core.at("material_failed_returns").get<long long>();
    wall_before_restart_s_ = core.at("wall_time_s").get<double>();

    const json& tools = state.at("tools");
    if (tools.size() != tools_.size()) throw std::runtime_error("another number of tools");
    for (std::size_t k = 0; k < tools_.size(); ++k) {
      RigidTool& t = tools_[k];
      const json& s = tools[k];
      if (s.at("name").get<std::string>() != t.name()) throw std::runtime_error("tool " + std::to_string(k) + " is another tool");
      t.axial_offset_m = s.at("axial_offset_m").get<double>();
      t.axial_velocity_m_s = s.at("axial_velocity_m_s").get<double>();
      t.angle_rad = s.at("angle_rad").get<double>();
      t.angular_velocity_rad_s = s.at("angular_velocity_rad_s").get<double>();
      const json& f = s.at("reaction_force_N");
      t.reaction_force_N = Eigen::Vector3d(f.at(0).get<double>(), f.at(1).get<double>(), f.at(2).get<double>());
      t.reaction_torque_Nm = s.at("reaction_torque_Nm").get<double>();
      t.power_W = s.at("power_W").get<double>();
      t.friction_heat_W = s.value("friction_heat_W", 0.0);  // absent from checkpoints before 2026-12-06
      t.work_J = s.at("work_J").get<double>();
    }

    const json& signals = state.at("signals");
    for (const auto& [name, value] : signals.at("measured").items())
      if (const SignalBus::Signal* s = signals_.measured(name)) *s->value = number(value);
    for (const auto& [name, value] : signals.at("commands").items())
      if (const SignalBus::Signal* s = signals_.command(name)) *s->value = number(value);

    const json& friction = state.at("friction_history");
    if (friction.size() != contact_.history_tools()) throw std::runtime_error("another number of friction memories");
    for (std::size_t t = 0; t < friction.size(); ++t) {
      std::vector<FrictionHistoryEntry> entries;
      entries.reserve(friction[t].size());
      for (const json& e : friction[t])
        entries.push_back({e.at(0).get<std::int64_t>(), {e.at(1).get<double>(), e.at(2).get<double>(), e.at(3).get<double>()}});
      contact_.restore_friction_history(t, std::move(entries));
    }

    const json& cursor = state.at("cursor");
    cursor_.frame = cursor.at("frame").get<int>();
    cursor_.checkpoint = cursor.at("checkpoint").get<int>();
    // The same interval goes on on the run's grid; a restart that changes an interval starts its
    // grid at the checkpoint's time. (The first checkpoints of 2026-12-02 did not store the
    // intervals: theirs go on on the saved grid.)
    auto next = [&](const char* key, const char* interval_key, double interval) {
      const double saved = cursor.at(key).get<double>();
      return !cursor.contains(interval_key) || cursor.at(interval_key).get<double>() == interval ? saved
                                                                                                  : time_ + interval;
    };
    cursor_.next_output = next("next_output_s", "output_interval_s", settings_.output_interval_s);
    cursor_.next_history = next("next_history_s", "history_interval_s", settings_.history_interval_s);
    cursor_.next_checkpoint = next("next_checkpoint_s", "checkpoint_interval_s", settings_.checkpoint_interval_s);
    cursor_.max_kinetic_to_work = cursor.at("max_kinetic_to_work").get<double>();

    process_->restore_state(state.at("process"));
    controllers_.restore_state(state.at("controllers"));
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(file, "", std::string("cannot restart from this checkpoint: ") + e.what());
  }
  if (settings_.thermal.enabled) {
    std::copy(extra[0].values.begin(), extra[0].values.end(), conductivity_.begin());
    std::copy(extra[1].values.begin(), extra[1].values.end(), specific_heat_.begin());
    const double* hc = fields_.f64(field::convection_coefficient);
    any_convection_ = std::any_of(hc, hc + count_, [](double c) { return c > 0.0; });
  }
  restarted_from_ = checkpoint;
  restart_step_ = step_;
  restart_time_s_ = time_;
}

}  // namespace sphforge
