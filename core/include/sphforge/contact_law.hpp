// Contact (wall/friction) law plugin interface. The core computes the normal penalty force of
// every particle touching a rigid tool (docs/theory.md, eq. contact-normal) and hands the whole
// batch of contacts to the tool's friction law, which returns the tangential forces.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace sphforge {

/// Structure-of-arrays batch of particle-tool contacts for one tool and one step.
struct ContactBatch {
  std::size_t count = 0;
  double dt = 0.0;                          ///< s
  const std::size_t* particle = nullptr;    ///< particle index of each contact
  const double* mass = nullptr;             ///< kg
  const double* normal = nullptr;           ///< 3 per contact, unit, pointing into the workpiece
  const double* normal_force = nullptr;     ///< N, >= 0 (magnitude of the penalty force)
  const double* penetration = nullptr;      ///< m, >= 0
  const double* tangential_velocity = nullptr;  ///< 3 per contact, particle minus wall, v - (v.n) n (m/s)
  const double* contact_area = nullptr;     ///< m^2, particle's share of the surface (dx^2)
  const double* yield_stress = nullptr;     ///< Pa, from the material (infinity if none)
  double* tangential_force = nullptr;       ///< 3 per contact, OUT: force on the particle (N)
  double* sticking = nullptr;               ///< OUT: 1 when the contact sticks, else 0
};

class ContactLaw {
 public:
  virtual ~ContactLaw() = default;
  /// True if the law needs the yield stress (the core then asks the material for it).
  virtual bool needs_yield_stress() const { return false; }
  virtual void tangential_forces(ContactBatch& batch) const = 0;
};

}  // namespace sphforge
