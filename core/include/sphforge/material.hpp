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

  /// Current yield stress (Pa) of each particle, written into `out` (count values), used by
  /// friction laws such as Coulomb-Tresca. Default: no yield limit (infinity).
  virtual void yield_stress(const MaterialBatch& batch, double* out) const;
};

}  // namespace sphforge
