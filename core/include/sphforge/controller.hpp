// Controller plugin interface: reads measured signals, writes commanded quantities, at its own
// sampling interval. Never touches particle arrays.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sphforge/signals.hpp"

namespace sphforge {

struct HistoryColumn {
  std::string name;            ///< ends in its unit, e.g. "ram_force_N"
  const double* value = nullptr;
};

class Controller {
 public:
  virtual ~Controller() = default;
  /// Adds the commands this controller offers to other controllers (e.g. a PID's target, which a
  /// schedule may drive). Called for every controller before any bind().
  virtual void declare(SignalBus& /*bus*/) {}
  /// Looks up the signals named in its parameters; throws InputError for unknown names.
  virtual void bind(SignalBus& bus) = 0;
  /// Called every step with the current time; the controller decides when it samples.
  virtual void update(double time_s, double dt_s) = 0;
  /// Extra history columns (e.g. error, P/I/D parts).
  virtual std::vector<HistoryColumn> history_columns() const { return {}; }

  // Restart (checkpoint_NNNNNN.h5, `sphforge run --restart`; docs/checkpoints.md). A controller
  // whose update() keeps memory between calls (an integral, the last sample) returns it from
  // save_state() and takes it back in restore_state(); supports_restart() says that it does. The
  // default is false: the core then refuses to checkpoint a case that uses the controller rather
  // than continue it with its memory lost. Signal values need not be saved: the core saves every
  // signal of the bus.
  virtual bool supports_restart() const { return false; }
  virtual nlohmann::json save_state() const { return nlohmann::json::object(); }
  virtual void restore_state(const nlohmann::json& /*state*/) {}
};

}  // namespace sphforge
