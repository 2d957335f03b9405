#include "sphforge/signals.hpp"

#include <stdexcept>

namespace sphforge {

namespace {
void add(std::map<std::string, SignalBus::Signal>& map, const std::string& name, const std::string& unit,
         double* value) {
  if (!map.emplace(name, SignalBus::Signal{unit, value}).second)
    throw std::logic_error("signal '" + name + "' declared twice");
}
const SignalBus::Signal* find(const std::map<std::string, SignalBus::Signal>& map, const std::string& name) {
  auto it = map.find(name);
  return it == map.end() ? nullptr : &it->second;
}
std::vector<std::string> keys(const std::map<std::string, SignalBus::Signal>& map) {
  std::vector<std::string> out;
  for (const auto& [k, v] : map) out.push_back(k);
  return out;
}
const SignalBus::Signal& require(const std::map<std::string, SignalBus::Signal>& map, const ParamValues& p,
                                 const std::string& key, const char* kind, const char* offered) {
  const std::string& name = p.string(key);
  if (const SignalBus::Signal* s = find(map, name)) return *s;
  std::string list;
  for (const auto& [k, v] : map) list += (list.empty() ? "" : ", ") + k;
  p.fail(key, std::string("unknown ") + kind + " '" + name + "'; " + offered + ": " + (list.empty() ? "(none)" : list));
}
}  // namespace

const SignalBus::Signal& SignalBus::require_measured(const ParamValues& p, const std::string& key) const {
  return require(measured_, p, key, "measured signal", "this process measures");
}
const SignalBus::Signal& SignalBus::require_command(const ParamValues& p, const std::string& key) const {
  return require(commands_, p, key, "command", "commands available");
}

void SignalBus::add_measured(const std::string& name, const std::string& unit, double* value) {
  add(measured_, name, unit, value);
}
void SignalBus::add_command(const std::string& name, const std::string& unit, double* value) {
  add(commands_, name, unit, value);
}
const SignalBus::Signal* SignalBus::measured(const std::string& name) const { return find(measured_, name); }
const SignalBus::Signal* SignalBus::command(const std::string& name) const { return find(commands_, name); }
std::vector<std::string> SignalBus::measured_names() const { return keys(measured_); }
std::vector<std::string> SignalBus::command_names() const { return keys(commands_); }

}  // namespace sphforge
