// Material plugin interface: equation of state and deviatoric stress update for one body.
//
// The core applies the objective (Jaumann) rotation of the deviatoric stress (docs/theory.md,
// eq. jaumann) before calling update_stress; the material then adds the elastic predictor
// 2G (D - tr(D)/3 I) dt, performs its return mapping and computes the pressure from its
// equation of state. All calls act on a whole contiguous particle range (no per-particle
// virtual call).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sphforge/fields.hpp"

namespace sphforge {

/// Arrays of one body's particles, already offset to the body's first particle.
struct MaterialBatch {
  std::size_t count = 0;
  double dt = 0.0;                       ///< s
  const double* velocity_gradient = nullptr;  ///< 9 per particle, L_ab = dv_a/dx_b (1/s)
  const double* density = nullptr;       ///< kg/m^3
  double* deviatoric_stress = nullptr;   ///< 6 per particle (xx yy zz xy yz xz), Pa; in: rotated, out: updated
  double* pressure = nullptr;            ///< Pa, out
  FieldRegistry* fields = nullptr;       ///< optional fields the material declared
  std::size_t first = 0;                 ///< index of the body's first particle in `fields`
  /// Thermal scenes only (null when isothermal): temperature (K), and the specific heat source
  /// (W/kg) the material adds its plastic heat to.
  const double* temperature = nullptr;
  double* heat_source = nullptr;
  /// numerics.time_scaling f: the simulated strain rates are f times the physical ones, so a
  /// rate-dependent law evaluates its rate term at rate / f (docs/theory.md eq. 25).
  double time_scaling = 1.0;
};

/// Thermal properties of one body's particles, evaluated by the material each step.
struct ThermalBatch {
  std::size_t count = 0;
  const double* temperature = nullptr;  ///< K
  double* conductivity = nullptr;       ///< W/(m K), out
  double* specific_heat = nullptr;      ///< J/(kg K), out
  FieldRegistry* fields = nullptr;
  std::size_t first = 0;
};

class Material {
 public:
  virtual ~Material() = default;

  /// Fields this material reads or writes besides the standard ones in MaterialBatch
  /// (e.g. plastic_strain). Only these get allocated.
  virtual std::vector<FieldInfo> fields() const { return {}; }

  virtual double reference_density() const = 0;     ///< kg/m^3
  /// Speed of the fastest elastic wave (m/s), used by the CFL time step limit.
  virtual double wave_speed() const = 0;
  /// Shear modulus (Pa), used by artificial-stress and contact-stiffness estimates.
  virtual double shear_modulus() const = 0;

  /// Called once after allocation, before the first step (e.g. to set initial yield stress).
  virtual void initialize(FieldRegistry& /*fields*/, std::size_t /*first*/, std::size_t /*count*/) {}

  /// Elastic predictor, return mapping and equation of state for the whole batch.
  virtual void update_stress(MaterialBatch& batch) = 0;

  /// True when the material has thermal properties (needed by cases with a "thermal" section).
  virtual bool conducts_heat() const { return false; }
  /// Conductivity and specific heat at the particles' temperatures (only called when
  /// conducts_heat()). Temperature-dependent laws belong here.
  virtual void thermal_properties(ThermalBatch& /*batch*/) const {}

  /// Current yield stress (Pa) of each particle, written into `out` (count values), used by
  /// friction laws such as Coulomb-Tresca. Default: no yield limit (infinity).
  virtual void yield_stress(const MaterialBatch& batch, double* out) const;

  /// Return mappings that hit the iteration cap without meeting the yield-condition tolerance,
  /// summed over the run (summary.json `material_failed_returns`; 0 for a law without iteration).
  virtual long long failed_returns() const { return 0; }
};

}  // namespace sphforge
