// Penalty contact between particles and rigid tools (docs/theory.md eqs. 10-12, 18a-18f). The
// normal force is a damped penalty spring; the tangential force comes from the tool's friction-law
// plugin, called once per tool with the whole batch of touching particles. The pass also sums each
// tool's reaction and torque and books the friction heat (eq. 18e).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sphforge/contact_law.hpp"
#include "sphforge/material.hpp"
#include "sphforge/tool.hpp"

namespace sphforge {

struct ContactSettings {
  double stiffness_factor = 1.0;  ///< kappa in k = kappa * M * dx (M: P-wave modulus rho0 c^2)
  double damping_ratio = 0.2;     ///< zeta: fraction of critical damping of the particle-spring
  /// Fraction of the friction heat that enters the workpiece particle (eq. 18f); the rest goes
  /// to the tool: into its attached thermal particles (eq. 91), or out of the model when the
  /// tool has none (thermally inert, docs/contact.md).
  double heat_to_workpiece = 0.5;
};

/// What one contact pass reads and writes (particle arrays, n mechanical particles).
struct ContactArrays {
  const double* x = nullptr;             ///< m, 3 per particle
  const double* v = nullptr;             ///< m/s, 3 per particle
  const double* mass = nullptr;          ///< kg (inertial)
  const double* acceleration = nullptr;  ///< m/s^2, 3 per particle, from every other force
  const double* yield = nullptr;         ///< Pa, null when no law needs it
  std::size_t n = 0;
  double dt = 0.0;
  double* force = nullptr;               ///< N, 3 per particle, contact forces are added
  /// W/kg of physical mass, the workpiece's share of the friction heat is added (null: isothermal)
  double* heat_source = nullptr;
  double mass_scaling = 1.0;             ///< inertial / physical mass (eq. 24)
  /// Particle ids (field `id`): the key of the friction laws' per-contact memory, which the pass
  /// keeps for the touching particles only (PenaltyContact::friction_history); the id, unlike the
  /// index, follows the particle through reordering and removal. Needed when a law needs_history().
  const std::int64_t* id = nullptr;
  /// Per tool (null: none does): 1 when it carries thermal particles that take its share of the
  /// friction heat (eq. 91); the pass then records that share per contact (PenaltyContact::tool_heat()).
  const unsigned char* tool_takes_heat = nullptr;
  /// Per-particle smoothing lengths of a scene of several spacings (null: all particles have the
  /// configured spacing), eq. 141: particle i of spacing s_i = h_i spacing_per_h touches the wall at
  /// s_i / 2, its share of the surface is s_i^2 and its penalty stiffness k s_i / s. The configured
  /// spacing must then be the largest.
  const double* smoothing_length = nullptr;
  double spacing_per_h = 0.0;  ///< 1 / h_over_dx
  /// Storage idle during the pass (the caller's pass scratch) that it may use for its per-particle
  /// indices (12 bytes per particle) instead of holding its own; overwritten. Empty: none lent.
  std::span<double> borrow;
};

/// The tool's share (1 - phi) |f_t| |v_t| of one contact's friction heat (eqs. 18e-18f), for the
/// tool's thermal particles (engine/tool_heat.hpp, eq. 91).
struct ToolHeatRecord {
  std::size_t tool = 0;
  std::size_t particle = 0;  ///< the workpiece particle in contact
  double heat_W = 0.0;
};

/// One touching particle's friction memory (ContactBatch::history, 3 numbers, N for `coulomb`).
struct FrictionHistoryEntry {
  std::int64_t id = 0;  ///< the particle's id (field `id`)
  double value[3] = {0.0, 0.0, 0.0};
};

/// Per-tool contact statistics of the last pass (history.csv columns <tool>_...).
struct ToolContactStats {
  std::size_t contacts = 0;
  double penetration_mean_m = 0.0, penetration_max_m = 0.0;
  double sticking_fraction = 0.0;
  double friction_heat_W = 0.0;          ///< sum |f_t| |v_t| (eq. 18e)
  double heat_to_workpiece_W = 0.0;      ///< the workpiece's share of it (eq. 18f)
  double heat_to_tool_W = 0.0;           ///< the share recorded for the tool's thermal particles (eq. 91)
};

class PenaltyContact {
 public:
  /// Tangential (friction) law for each tool, same order as the tools. `spacing`: the largest particle
  /// spacing; `finest_spacing` (0: the same) the smallest, whose stiffness the laws get (eq. 141).
  void configure(const ContactSettings& settings, std::vector<const ContactLaw*> laws, double spacing,
                 double p_wave_modulus, double finest_spacing = 0.0);

  /// Spring stiffness k (N/m) of one particle against a wall.
  double stiffness() const { return stiffness_; }
  /// Largest stable step for a particle of mass m on the contact spring (theory eq. 12).
  double stable_time_step(double min_mass) const;

  /// Adds contact forces to `a.force`, sets tool reactions, and returns the number of contacts.
  std::size_t apply(std::vector<RigidTool>& tools, ContactArrays& a);

  /// Fraction of contacts that stuck in the last apply() (0 when none).
  double sticking_fraction() const { return sticking_fraction_; }
  const std::vector<ToolContactStats>& tool_stats() const { return stats_; }
  /// The tools' shares of the friction heat of the last apply(), one record per contact with a
  /// tool that takes heat, in contact order (deterministic).
  const std::vector<ToolHeatRecord>& tool_heat() const { return tool_heat_; }
  /// The friction memory of tool `tool` after the last apply(): one entry per particle touching it,
  /// ascending ids; empty when its law keeps none. A particle not listed has none (eq. 18b: zero).
  const std::vector<FrictionHistoryEntry>& friction_history(std::size_t tool) const { return history_[tool]; }
  /// Particle `id`'s friction memory with tool `tool`, or null when it has none (not touching):
  /// for the symmetry wrap, which transforms it as it transforms the vector fields (eq. 32).
  FrictionHistoryEntry* friction_history_entry(std::size_t tool, std::int64_t id);
  /// Restart (docs/checkpoints.md): replaces tool `tool`'s friction memory with `entries`
  /// (ascending ids, as friction_history() gave them).
  void restore_friction_history(std::size_t tool, std::vector<FrictionHistoryEntry> entries) {
    history_.at(tool) = std::move(entries);
  }
  /// Number of tools whose friction memory friction_history() holds (those of configure()).
  std::size_t history_tools() const { return history_.size(); }
  /// Writes tool `tool`'s friction memory as 3 numbers per particle (0 where none) for the output
  /// writers: particle i of `id` (n particles) into out[3 i .. 3 i + 2].
  void friction_history_dense(std::size_t tool, const std::int64_t* id, std::size_t n, double* out) const;

  /// Memory held by the friction memory (both copies, capacities), in bytes; part of bytes().
  std::size_t history_bytes() const {
    std::size_t total = history_next_.capacity() * sizeof(FrictionHistoryEntry);
    for (const auto& h : history_) total += h.capacity() * sizeof(FrictionHistoryEntry);
    return total;
  }
  /// Memory held by the scratch arrays and the friction memory (bytes).
  std::size_t bytes() const {
    std::size_t total = (near_x_.held() + near_distance_.held() + near_normal_.held()) * sizeof(double) +
                        (own_slot_of_.capacity() + own_cell_of_.capacity() + cell_start_.capacity() +
                         own_cell_particles_.capacity() + cell_fill_.capacity() + near_particles_.capacity()) *
                            sizeof(std::uint32_t) +
                        particle_.capacity() * sizeof(std::size_t) + cell_near_.capacity() +
                        tool_heat_.capacity() * sizeof(ToolHeatRecord) + history_bytes();
    for (const auto* b : {&batch_mass_, &batch_normal_, &batch_fn_, &batch_gap_, &batch_vn_, &batch_damping_,
                          &batch_vt_, &batch_acc_, &batch_area_, &batch_yield_, &batch_history_, &batch_ft_,
                          &batch_stick_, &batch_vwall_})
      total += b->held() * sizeof(double);
    return total;
  }

 private:
  ContactSettings settings_;
  std::vector<const ContactLaw*> laws_;
  double spacing_ = 0.0, stiffness_ = 0.0;
  double law_stiffness_ = 0.0;  ///< the finest particle's stiffness, the laws' scalar k (eq. 141)
  double sticking_fraction_ = 0.0;
  std::vector<ToolContactStats> stats_;
  std::vector<ToolHeatRecord> tool_heat_;
  // Friction memory per tool, for the touching particles only, sorted by id (a scene pays for the
  // contacts it has, not 24 bytes per particle and tool); history_next_ is the next pass's copy
  // under construction, swapped in at the end of the pass (no allocation once warmed up).
  std::vector<std::vector<FrictionHistoryEntry>> history_;
  std::vector<FrictionHistoryEntry> history_next_;
  // Scratch, kept between steps so that the pass does not allocate once warmed up. Per particle
  // only 4-byte indices (12 bytes in all: slot_of_, cell_of_, cell_particles_, in the borrowed
  // storage when ContactArrays::borrow is large enough, else in the own_ arrays); the distances and
  // normals are held for the particles of the near cells only (LentArray below).
  static constexpr std::uint32_t kFar = 0xffffffffu;  ///< slot_of_: not in a near cell
  std::uint32_t* slot_of_ = nullptr;  ///< each particle's place in near_particles_, or kFar
  std::uint32_t* cell_of_ = nullptr;  ///< each particle's culling cell
  std::uint32_t* cell_particles_ = nullptr;  ///< the particles sorted by cell
  std::vector<std::uint32_t> own_slot_of_, own_cell_of_, own_cell_particles_;
  std::span<double> lent_;    ///< the storage lent to this pass (ContactArrays::borrow)
  std::size_t lent_base_ = 0;  ///< doubles of lent_ that the indices take
  std::vector<std::size_t> particle_;   ///< the touching particles, ascending (the law's batch)
  // Culling cells (edge 2 dx) over the particles, rebuilt at every pass.
  void bin_particles(const double* x, std::size_t n);
  double cell_edge_ = 0.0, grid_lo_[3] = {0, 0, 0};
  std::size_t grid_dims_[3] = {1, 1, 1};
  std::vector<std::uint32_t> cell_start_, cell_fill_;
  std::vector<unsigned char> cell_near_;
  // The per-tool arrays below (near cells' query, the law's batch) are dead once the tool's sums are
  // made. They live in the lent storage after the 12 bytes of indices per particle when it has room
  // (the pass scratch holds 7 doubles per particle; these need 60 bytes per near particle and
  // 160 per touching one), else in their own vectors: a scene does not hold both.
  class LentArray {
   public:
    double* data() { return p_; }
    double& operator[](std::size_t i) { return p_[i]; }
    const double& operator[](std::size_t i) const { return p_[i]; }
    std::size_t held() const { return own_.capacity(); }  ///< doubles held by this object (not lent)
    /// `count` doubles from `lent` (advancing `used`) when they fit, else from the own vector.
    void resize(std::size_t count, std::span<double> lent, std::size_t& used) {
      if (used + count <= lent.size()) {
        std::vector<double>().swap(own_);
        p_ = lent.data() + used;
        used += count;
      } else {
        own_.resize(count);
        p_ = own_.data();
      }
    }

   private:
    std::vector<double> own_;
    double* p_ = nullptr;
  };
  // Particles of the near cells (in cell order) and their batch query (positions, distances, normals).
  std::vector<std::uint32_t> near_particles_;
  LentArray near_x_, near_distance_, near_normal_;
  LentArray batch_mass_, batch_normal_, batch_fn_, batch_gap_, batch_vn_, batch_damping_, batch_vt_,
      batch_acc_, batch_area_, batch_yield_, batch_history_, batch_ft_, batch_stick_, batch_vwall_;
};

}  // namespace sphforge
