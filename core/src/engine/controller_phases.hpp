// The controllers of a case and its process phases (docs/theory.md eq. 65): controllers listed in
// "controllers" act during the whole run; "phases" is a sequence, each with its own controllers and
// an end condition (a duration, or a measured signal crossing a threshold). Only the current phase's
// controllers are updated, with the time since their phase began, so a schedule in a phase is
// written in phase time ("a 10 s linear transition").
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sphforge/controller.hpp"
#include "sphforge/parameters.hpp"
#include "sphforge/signals.hpp"

namespace sphforge {

class ControllerPhases {
 public:
  /// Creates one controller from its case section (a plugin object) at `pointer`.
  using MakeController = std::function<std::unique_ptr<Controller>(const json& section, const std::string& pointer)>;

  /// Reads "controllers" and "phases" of the validated top level `root`, creates every controller,
  /// then declares and binds all of them on `bus` (phase controllers too, so that a bad signal name
  /// in a late phase is an input error before the run). Throws InputError.
  void load(const ParamValues& root, const MakeController& make, SignalBus& bus);

  /// Ends the current phase when its condition holds (at most one phase per step), then updates the
  /// run-long controllers (with `time`) and the current phase's (with the time since it began).
  void update(double time, double dt);

  /// True once the last phase's own end condition has held: the run is over.
  bool finished() const { return finished_; }
  std::vector<HistoryColumn> history_columns() const;
  /// {"phases": [{"name", "start_s", "end_s"}...]} for summary.json; empty without phases.
  json summary() const;

  /// Restart (docs/checkpoints.md): the JSON pointer of the first controller that cannot be
  /// checkpointed (Controller::supports_restart), empty when every one can.
  std::string first_without_restart() const;
  /// The current phase, the phases' start and end times and every controller's own state.
  json save_state() const;
  /// Takes back what save_state() wrote for the same case (same controllers and phases).
  void restore_state(const json& state);

 private:
  struct Phase {
    std::string name;
    std::vector<std::unique_ptr<Controller>> controllers;
    std::vector<std::string> pointers;  ///< case pointers of the controllers, for messages
    double duration = std::numeric_limits<double>::infinity();  ///< s
    const double* signal = nullptr;                              ///< measured signal of the end condition
    double above = std::numeric_limits<double>::infinity();      ///< ends when signal > above
    double below = -std::numeric_limits<double>::infinity();     ///< ends when signal < below
    double start = std::numeric_limits<double>::quiet_NaN(), end = std::numeric_limits<double>::quiet_NaN();
    bool has_end() const { return duration < std::numeric_limits<double>::infinity() || signal != nullptr; }
    bool ended(double time) const;
  };
  std::vector<std::unique_ptr<Controller>> run_long_;
  std::vector<std::string> run_long_pointers_;  ///< case pointers, for messages
  std::vector<Phase> phases_;
  std::size_t current_ = 0;
  double phase_number_ = 0.0;  ///< history column `phase_1`: 1-based index of the current phase
  bool finished_ = false;
};

}  // namespace sphforge
