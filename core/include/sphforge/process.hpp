// Process plugin interface: geometry, particle generation, tool kinematics, boundary
// conditions and the quantities a process measures.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "sphforge/controller.hpp"
#include "sphforge/fields.hpp"
#include "sphforge/signals.hpp"
#include "sphforge/tool.hpp"

namespace sphforge {

/// Given to Process::build: the process creates its bodies and tools through it.
class SceneBuilder {
 public:
  virtual ~SceneBuilder() = default;
  /// Adds a deformable body of particles on a lattice of spacing `spacing_m` (volume spacing^3
  /// each) made of the case's material. Returns the body index.
  virtual std::size_t add_body(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                               double spacing_m) = 0;
  /// Adds a rigid tool and returns its index.
  virtual std::size_t add_tool(RigidTool tool) = 0;
};

struct BodyRange {
  std::string name;
  std::size_t first = 0, count = 0;
  double spacing_m = 0.0;
};

/// What a process sees of the running simulation.
struct ProcessContext {
  double time_s = 0.0;
  double dt_s = 0.0;
  long long step = 0;
  FieldRegistry* fields = nullptr;
  std::vector<RigidTool>* tools = nullptr;
  const std::vector<BodyRange>* bodies = nullptr;
};

class Process {
 public:
  virtual ~Process() = default;
  /// Fields the process needs beyond the core's (e.g. tracer flags).
  virtual std::vector<FieldInfo> fields() const { return {}; }
  /// Creates bodies and tools.
  virtual void build(SceneBuilder& scene) = 0;
  /// Declares measured signals and commandable quantities.
  virtual void bind_signals(SignalBus& bus) = 0;
  /// Before each step: applies commands to tool kinematics and boundary conditions.
  virtual void before_step(ProcessContext& ctx) = 0;
  /// After each step: updates measured quantities from tool reactions and particles.
  virtual void measure(ProcessContext& ctx) = 0;
  /// True when the process has reached its own end (e.g. full ram stroke).
  virtual bool finished(const ProcessContext& /*ctx*/) const { return false; }
  /// History columns (names end in their unit).
  virtual std::vector<HistoryColumn> history_columns() const = 0;
  /// Metrics for summary.json at the end of the run.
  virtual nlohmann::json metrics() const { return nlohmann::json::object(); }
};

}  // namespace sphforge
