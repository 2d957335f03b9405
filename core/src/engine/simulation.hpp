// One run of a case: validates the case and builds the scene (plugins, particles, tools) in the
// constructor without touching the disk, then run() advances it and writes the outputs.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/contact.hpp"
#include "engine/controller_phases.hpp"
#include "engine/neighbours.hpp"
#include "engine/sph_operators.hpp"
#include "engine/symmetry.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/plugin_loader.hpp"

namespace sphforge {

/// numerics.momentum_correction: the part of sigma the correction C multiplies in eq. 7.
enum class MomentumCorrection { Full, Deviatoric, None };

/// Settings of the core read from the case ("numerics", "run", "contact").
struct CoreSettings {
  std::string case_name;
  KernelKind kernel = KernelKind::CubicSpline;
  double h_over_dx = 1.3;
  double cfl = 0.3;
  double neighbour_skin = 0.2;  ///< Verlet skin, fraction of h
  double thermal_neighbour_skin = 0.2;  ///< Verlet skin of the thermal lists, fraction of h (theory section 7)
  double domain_margin_m = -1.0;  ///< beyond the initial box: instability (-1: the box's size)
  bool gradient_correction = true;
  /// Which part of sigma the correction C multiplies in eq. 7: all (eq. 7), none (A = sigma, eq. 7a) or the
  /// deviatoric part only (A = S C - p I, eq. 7b).
  MomentumCorrection momentum_correction = MomentumCorrection::Full;
  bool second_order_gradient = false;  ///< numerics.gradient_correction_order = "second" (section 18)
  ArtificialViscosity viscosity;
  ArtificialStress artificial_stress;
  ContactSettings contact;
  double mass_scaling = 1.0;  ///< eq. 24
  double time_scaling = 1.0;  ///< eq. 25
  double xsph = 0.0;          ///< eq. 19, 0: off
  double density_diffusion = 0.0;  ///< delta of eq. 4a, 0: off
  SymmetrySettings symmetry;  ///< numerics.symmetry (section 11, eqs. 28-32); inactive by default
  struct Thermal {
    bool enabled = false;
    double initial_temperature_K = 293.15, ambient_temperature_K = 293.15;
    double convection_coefficient = 0.0;  ///< W/(m^2 K) on free surfaces unless the process sets it
    double time_step_factor = 0.1;        ///< eq. 26
    /// Conduction, convection and the tools' heat on a step of their own, up to the limit of eq. 26
    /// (eq. 26b); the heat sources still act every mechanical step. Off: every step is a thermal step.
    bool subcycling = false;
  } thermal;
  double end_time_s = 0.0;
  double output_interval_s = 0.0;
  double history_interval_s = 0.0;
  long long max_steps = 0;  ///< 0: no limit
  double checkpoint_interval_s = 0.0;  ///< run.checkpoint_interval; 0: no checkpoints (docs/checkpoints.md)
  int threads = 0;          ///< 0: OpenMP default
};

/// How progress is shown: a bar on a terminal, periodic lines otherwise, or nothing.
enum class ProgressMode { Auto, Bar, Lines, Quiet };

/// A pass of the per-step pipeline with the fields it reads and writes. The registry allocates
/// exactly the union of what the assembled passes (and plugins) declare.
struct PassInfo {
  std::string name;
  std::vector<FieldInfo> reads, writes;
};

class Simulation {
 public:
  Simulation(const CaseDocument& doc, PluginLoader& loader);
  ~Simulation();

  struct RunResult {
    int exit_code = 0;  ///< 0 done, 3 instability
    std::string message;
  };
  RunResult run(const std::filesystem::path& out_dir, ProgressMode progress);
  /// Continues a run from a checkpoint (`sphforge run CASE --restart FILE`, docs/checkpoints.md):
  /// initialises the rebuilt scene as a new run would, then takes the particle fields, the tools,
  /// the signals, the plugins' state and the core's ledgers from `checkpoint`; run() then goes on
  /// from there. The case must be the one that wrote the checkpoint except for its "run" section.
  /// Throws InputError (file, what differs) for a file that is not a checkpoint of this case, and
  /// for a process or controller plugin that keeps no restart state. Call before run().
  void restore(const std::filesystem::path& checkpoint);

  const CoreSettings& settings() const { return settings_; }
  std::size_t particle_count() const { return count_; }
  const FieldRegistry& fields() const { return fields_; }
  const std::vector<PassInfo>& passes() const { return passes_; }
  const std::vector<RigidTool>& tools() const { return tools_; }
  const std::vector<BodyRange>& bodies() const { return bodies_; }
  const NeighbourList& neighbours() const { return neighbours_; }
  /// Lists over all particles (thermal-only ones included) of the last thermal pass; empty when
  /// every particle is mechanical (the thermal pass then uses neighbours()).
  const NeighbourList& thermal_neighbours() const { return thermal_neighbours_; }
  const Symmetry& symmetry() const { return symmetry_; }
  /// Ghost particles (images across the symmetry cuts) of the last neighbour-list build.
  std::size_t ghost_count() const { return symmetry_.ghost_count(); }
  long long neighbour_builds() const { return neighbours_.builds(); }
  /// Smoothing length h (m): h_over_dx times the particle spacing.
  double smoothing_length() const { return h_; }
  /// One item of memory_breakdown(): what holds the memory and how many bytes.
  struct MemoryItem {
    std::string name;
    std::size_t bytes = 0;
  };
  /// Memory held for the particles, item by item (capacities, not sizes): every registered field,
  /// the neighbour lists and their build scratch, the contact scratch, the per-step scratch of the
  /// passes, the symmetry ghosts' extended arrays and the thermal arrays. docs/bench.md, "Memory per
  /// particle", lists them for the benchmark case.
  std::vector<MemoryItem> memory_breakdown() const;
  /// The sum of memory_breakdown() (bytes).
  std::size_t memory_bytes() const;
  /// The particles are reordered by cell (Morton order within each body, engine/reorder.hpp)
  /// just before every this-many-th neighbour-list build, starting with the first.
  static constexpr long long kReorderEveryBuilds = 8;

 private:
  class Builder;
  void step();
  double stable_time_step();
  void check_stability() const;
  std::vector<std::string> history_header() const;
  std::vector<double> history_row() const;
  double kinetic_energy() const;
  void mechanics_rates();
  BondFailure bond_failure_inputs(std::size_t n);
  void velocity_gradient_pass(const double* xe, const double* ve, const double* volume, double* correction,
                              double* second_b, double* L, double* condition, std::size_t n,
                              const BondFailure& failure);
  std::size_t pass_scratch_per_particle(bool stress_c_in_l) const;
  void build_mechanical_lists(const double* x, std::size_t n, std::size_t per_particle, bool transient);
  void output_velocity_gradient(std::vector<double>& density_rate, std::vector<double>& condition);
  void thermal_rates();
  /// Lists, ghosts, volumes and properties of the thermal pass, the tools' heat of `tool_heat`
  /// deposited into their attached bodies (eq. 91, into heat_source), and the conduction and
  /// convection heat flows into heat_W_ (eqs. 20-23).
  void thermal_heat_flows(const std::vector<ToolHeatRecord>& tool_heat);
  /// thermal_rates() with thermal.subcycling (eq. 26b).
  void thermal_rates_subcycled();
  void integrate();
  void evaluate_thermal_properties();
  void prepare_run();
  double thermal_time_step() const;
  ProcessContext context();
  /// The run's state besides the particle fields, as a checkpoint stores it (engine/checkpoint.cpp).
  nlohmann::json checkpoint_state(double wall_time_s) const;
  /// Writes out_dir/checkpoint_NNNNNN.h5 (the next number) and marks the neighbour lists stale,
  /// so that this run and one restarted from the file rebuild them at the same step.
  void write_checkpoint(const std::filesystem::path& out_dir, double wall_time_s);
  /// The plugin (process or controller) that cannot be checkpointed, as "<what> at <pointer>";
  /// empty when every one can.
  std::string first_without_restart() const;

  CoreSettings settings_;
  std::string case_file_;
  nlohmann::json case_root_;   ///< the case as run (after --set): a checkpoint must match it
  std::string process_name_;
  PluginLoader& loader_;
  std::vector<std::unique_ptr<Material>> materials_;  ///< [0]: the case's "material"
  std::vector<std::string> material_keys_;           ///< "" for [0], else the key in "materials"
  std::vector<const Material*> material_views_;      ///< materials_ read-only, for ProcessContext::materials
  std::unique_ptr<Process> process_;
  std::vector<std::unique_ptr<ContactLaw>> contact_laws_;
  ControllerPhases controllers_;
  SignalBus signals_;

  FieldRegistry fields_;
  std::vector<PassInfo> passes_;
  std::vector<BodyRange> bodies_;
  std::vector<RigidTool> tools_;
  NeighbourList neighbours_;          ///< mechanical particles [0, mechanical_count_)
  NeighbourList thermal_neighbours_;  ///< all particles, only when there are thermal-only bodies
  PenaltyContact contact_;
  bool need_yield_ = false;
  std::vector<double> yield_scratch_;
  std::vector<double> scratch_;  ///< per-particle temporaries of the pair passes (volume, C/R; sigma C with symmetry)
  std::vector<std::uint64_t> tension_bits_;  ///< mark_tension() of the artificial stress R, 1 bit per point

  std::size_t count_ = 0, mechanical_count_ = 0;
  // Symmetry (engine/symmetry.hpp): the ghosts and the extended arrays [real | ghosts] that the
  // pair passes read; unused (empty) without symmetry.
  Symmetry symmetry_;
  std::vector<double> ext_x_, ext_v_, ext_m_, ext_rho_, ext_T_;
  /// With symmetry and thermal-only bodies: the ghosts of every particle (mechanical and
  /// thermal-only) for the thermal lists, and their extended positions (eq. 31).
  Symmetry thermal_symmetry_;
  std::vector<double> ext_thermal_x_;
  /// Bond failure (scenes with a failure criterion only): sigma and the failed flags of the step's
  /// start, ghosts included (eq. 112).
  std::vector<double> bond_stress_, ext_failed_;
  /// Copies the real part [0, n) of `src` into ext and fills the ghosts; returns ext.data().
  double* extend(std::vector<double>& ext, const double* src, int components, bool position = false) {
    return extend(ext, src, components, position, symmetry_, mechanical_count_);
  }
  /// The same for the real particles [0, n) and the ghosts of `ghosts` (the thermal set, eq. 32a).
  static double* extend(std::vector<double>& ext, const double* src, int components, bool position,
                        const Symmetry& ghosts, std::size_t n);
  double wave_speed_ = 0.0;  ///< fastest mechanical wave, mass scaling included
  // Thermal scratch (thermal scenes only): properties, heat flow (W) and surface area (m^2).
  std::vector<double> conductivity_, specific_heat_, heat_W_, area_, thermal_volume_, physical_density_;
  std::vector<double> xsph_scratch_;
  /// Density diffusion (eq. 4a; scenes that enable it only): g (3 per particle and ghost) and the
  /// diffusive rate of the real particles.
  std::vector<double> density_gradient_, diffusion_rate_;
  /// Adds the diffusive rate of eq. 4a at the step's start densities (rho_e: real and ghosts) to drho.
  void density_diffusion_pass(const double* xe, const double* rho_e, const double* volume, const double* correction,
                              double* drho, std::size_t n, const BondFailure& failure);
  std::vector<std::pair<std::size_t, std::size_t>> wrap_moves_;  ///< particles the symmetry wrap moved, and their image
  double internal_energy_ = 0.0, dt_thermal_ = 0.0;
  bool any_convection_ = false;
  // Thermal-only bodies attached to tools (eqs. 90-91): whether any is, which tools take their
  // share of the friction heat, and per tool the friction heat and that share summed over steps (J).
  bool any_attached_ = false;
  std::vector<unsigned char> tool_takes_heat_;
  std::vector<double> tool_friction_heat_J_, tool_heat_to_tool_J_;
  bool thermal_lists_stale_ = false;  ///< a reorder permuted the particles behind the thermal lists
  /// thermal.subcycling (eq. 26b): time since the last thermal step (s, scaled), and per tool that
  /// takes heat the name of the field holding each contact particle's pending share (J) of it.
  double thermal_pending_s_ = 0.0;
  std::vector<std::string> pending_tool_heat_field_;
  std::vector<ToolHeatRecord> pending_tool_heat_;
  std::vector<double*> pending_fields_;  ///< this step's arrays of pending_tool_heat_field_ (null: none)
  double domain_min_[3] = {0, 0, 0}, domain_max_[3] = {0, 0, 0};  ///< particles outside: instability
  double domain_margin_used_m_ = 0.0;
  double spacing_ = 0.0, h_ = 0.0, min_mass_ = 0.0, initial_kinetic_energy_ = 0.0;
  /// Variable spacing (theory section 19): particles of several spacings, each with its smoothing
  /// length in the field `smoothing_length`; h_ is then the largest and h_min_ the smallest.
  bool variable_spacing_ = false;
  double h_min_ = 0.0;
  std::vector<double> point_support_;  ///< 2 h_i per point of a list build (eq. 140)
  /// The per-particle smoothing lengths (null with one spacing), and the supports 2 h_i for a
  /// neighbour build over the first `count` particles (null with one spacing).
  const double* smoothing_lengths() const;
  const double* point_supports(std::size_t count);
  /// Work the process's constraints (prescribed velocities) did, summed over the steps (eq. 27a):
  /// part of the energy ledger of the instability check, like the tools' work.
  double constraint_work_J_ = 0.0;
  /// Work of the body force (eq. 47), also part of the energy ledger.
  double body_force_work_J_ = 0.0;
  Eigen::Vector3d body_acceleration_ = Eigen::Vector3d::Zero();  ///< m/s^2, case section "body_force"
  Eigen::Vector3d body_oscillation_ = Eigen::Vector3d::Zero();   ///< m/s^2, amplitude of the cos(omega t) part
  Eigen::Vector3d body_now_ = Eigen::Vector3d::Zero();           ///< the body force of the current step
  double body_angular_frequency_ = 0.0;                          ///< rad/s
  std::vector<const ContactLaw*> tool_laws_;  ///< friction law of each tool
  double contact_time_s_ = 0.0;               ///< wall time spent in the contact pass
  std::vector<double> constrained_scratch_;  ///< v + dt a and a before the constraints (6 per particle)
  double time_ = 0.0, dt_ = 0.0, dt_initial_ = 0.0, dt_cfl_ = 0.0, dt_contact_ = 0.0;
  long long step_ = 0;
  std::size_t contacts_ = 0;
  /// Where the run loop stands, besides time_ and step_: what a checkpoint saves with the fields.
  struct RunCursor {
    int frame = 0;       ///< number of the next particle frame
    int checkpoint = 0;  ///< number of the next checkpoint
    double next_output = 0.0, next_history = 0.0, next_checkpoint = 0.0;
    double max_kinetic_to_work = 0.0;  ///< summary.json kinetic_to_work_ratio_max so far
  } cursor_;
  /// Restarted runs: the checkpoint, its step and time, and the wall time of the run before it.
  std::filesystem::path restarted_from_;
  long long restart_step_ = 0;
  double restart_time_s_ = 0.0, wall_before_restart_s_ = 0.0;
  long long failed_returns_before_restart_ = 0;
  std::vector<HistoryColumn> process_columns_, controller_columns_;
};

}  // namespace sphforge
