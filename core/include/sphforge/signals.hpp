// Named process signals: what a process measures (forces, displacements, temperatures) and what
// it lets a controller command (ram velocity, rotation speed). Controllers bind to names and
// never touch particle arrays.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "sphforge/parameters.hpp"

namespace sphforge {

class SignalBus {
 public:
  struct Signal {
    std::string unit;
    double* value = nullptr;
  };

  void add_measured(const std::string& name, const std::string& unit, double* value);
  void add_command(const std::string& name, const std::string& unit, double* value);

  /// nullptr when no such signal.
  const Signal* measured(const std::string& name) const;
  const Signal* command(const std::string& name) const;
  std::vector<std::string> measured_names() const;
  std::vector<std::string> command_names() const;

  /// The signal named by the string parameter `key` of `p`; an unknown name is an InputError at that
  /// parameter listing the signals the process offers (what `sphforge check` reports).
  const Signal& require_measured(const ParamValues& p, const std::string& key) const;
  const Signal& require_command(const ParamValues& p, const std::string& key) const;

 private:
  std::map<std::string, Signal> measured_, commands_;
};

}  // namespace sphforge
