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
#include "sphforge/material.hpp"
#include "sphforge/signals.hpp"
#include "sphforge/tool.hpp"

namespace sphforge {

/// A body of particles as a process describes it to the core.
struct BodySpec {
  std::string name;
  /// Particle centres on a lattice of spacing `spacing_m`; each particle has volume spacing^3.
  std::vector<Eigen::Vector3d> positions;
  double spacing_m = 0.0;
  /// Optional: each particle's own spacing (m), one per position, for a body with a refined zone
  /// (docs/theory.md section 19: each particle then has volume s_i^3 and smoothing length
  /// h_over_dx s_i). Empty: every particle has `spacing_m`.
  std::vector<double> particle_spacings_m;
  /// Key of the case's "materials" object; empty: the case's "material".
  std::string material;
  /// Initial velocity of each particle (m/s); empty: at rest.
  std::vector<Eigen::Vector3d> velocities;
  /// false: thermal-only particles (e.g. a conducting tool). They take part in heat conduction
  /// but in no mechanics pass, and the core does not move them unless they are attached.
  bool mechanics = true;
  /// Thermal-only bodies: the name of the tool they belong to. The core then places them every
  /// step from the tool's pose (docs/theory.md eq. 90) and puts the tool's share of the friction
  /// heat into them (eq. 91). Empty: not attached (the body stays where it is).
  std::string attached_to;
};

/// Given to Process::build: the process creates its bodies and tools through it.
class SceneBuilder {
 public:
  virtual ~SceneBuilder() = default;
  /// Adds a body and returns its index. Mechanical bodies come first in the particle arrays,
  /// thermal-only bodies after them, each in the order added. With `numerics.symmetry` the core
  /// keeps only the particles inside the symmetry region (docs/theory.md section 11): a process
  /// builds whole bodies and sees, through ProcessContext, only the simulated part.
  virtual std::size_t add_body(BodySpec body) = 0;
  /// Shorthand: a mechanical body at rest made of the case's material.
  std::size_t add_body(const std::string& name, const std::vector<Eigen::Vector3d>& positions, double spacing_m) {
    BodySpec spec;
    spec.name = name;
    spec.positions = positions;
    spec.spacing_m = spacing_m;
    return add_body(std::move(spec));
  }
  /// Shorthand: a thermal-only body of the case's material `material` (a key of "materials") attached
  /// to the tool named `tool`, which moves it and gives it its share of the friction heat
  /// (docs/theory.md eqs. 90-91).
  std::size_t add_tool_body(const std::string& name, std::vector<Eigen::Vector3d> positions, double spacing_m,
                            const std::string& material, const std::string& tool) {
    BodySpec spec;
    spec.name = name;
    spec.positions = std::move(positions);
    spec.spacing_m = spacing_m;
    spec.material = material;
    spec.mechanics = false;
    spec.attached_to = tool;
    return add_body(std::move(spec));
  }
  /// Adds a rigid tool and returns its index.
  virtual std::size_t add_tool(RigidTool tool) = 0;
};

/// A body's particles in the core's arrays: indices [first, first + count).
struct BodyRange {
  std::string name;
  std::size_t first = 0, count = 0;
  double spacing_m = 0.0;
  std::size_t material = 0;  ///< index into the scene's materials
  bool mechanics = true;
  long long attached_tool = -1;  ///< index of the tool a thermal-only body moves with (-1: none)
};

/// What a process sees of the running simulation.
struct ProcessContext {
  double time_s = 0.0;
  double dt_s = 0.0;
  long long step = 0;
  FieldRegistry* fields = nullptr;
  std::vector<RigidTool>* tools = nullptr;
  const std::vector<BodyRange>* bodies = nullptr;
  /// Particles [0, mechanical_count) take part in mechanics; the rest are thermal-only.
  std::size_t mechanical_count = 0;
  /// numerics.time_scaling: processes multiply their tool speeds by it (docs/theory.md eq. 25).
  double time_scaling = 1.0;
  /// The scene's materials, indexed by BodyRange::material, read-only: a process that models part of
  /// a body beyond its particles (friction_drilling's sheet beyond the disc, eq. 121b) takes that
  /// body's properties from here instead of repeating them in its own parameters. Reference density
  /// is the physical one (no mass scaling).
  const std::vector<const Material*>* materials = nullptr;
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
  /// Once, after the particles exist and before the first step (initial temperatures, convection
  /// coefficients of surface regions, ...).
  virtual void initialize(ProcessContext& /*ctx*/) {}
  /// Before each step: applies commands to tool kinematics and boundary conditions.
  virtual void before_step(ProcessContext& ctx) = 0;
  /// After every rate of the step is known (acceleration including contact, temperature rate)
  /// and before the integration: prescribed velocities, fixed regions, fixed temperatures.
  virtual void apply_constraints(ProcessContext& /*ctx*/) {}
  /// True when apply_constraints() may change particle velocities; the core then books the
  /// kinetic energy they add in its energy ledger (a scene without constraints pays nothing).
  virtual bool constrains_velocities() const { return false; }
  /// After each step: updates measured quantities from tool reactions and particles.
  virtual void measure(ProcessContext& ctx) = 0;
  /// True when the process has reached its own end (e.g. full ram stroke).
  virtual bool finished(const ProcessContext& /*ctx*/) const { return false; }
  /// History columns (names end in their unit).
  virtual std::vector<HistoryColumn> history_columns() const = 0;
  /// Metrics for summary.json at the end of the run.
  virtual nlohmann::json metrics() const { return nlohmann::json::object(); }

  // Restart (checkpoint_NNNNNN.h5, `sphforge run --restart`; docs/checkpoints.md). The core saves
  // the particle fields, the tools' poses, velocities and work, every signal of the bus and its own
  // ledgers; a process saves what it accumulates over steps (window averages, peaks, samples)
  // in save_state() and takes it back in restore_state(), which the core calls after initialize()
  // on the rebuilt scene and after the fields are restored. supports_restart() says that it does;
  // the default is false, and the core then refuses to checkpoint the case (exit 2) rather than
  // continue it with the process's memory lost.
  virtual bool supports_restart() const { return false; }
  virtual nlohmann::json save_state() const { return nlohmann::json::object(); }
  virtual void restore_state(const nlohmann::json& /*state*/) {}
};

}  // namespace sphforge
