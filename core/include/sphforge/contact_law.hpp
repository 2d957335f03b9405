// Contact (wall/friction) law plugin interface. The core computes the normal penalty force of
// every particle touching a rigid tool (docs/theory.md, eqs. 10-12) and hands the whole batch of
// contacts of one tool to that tool's friction law, which returns the tangential forces
// (docs/theory.md section 6, docs/contact.md).
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace sphforge {

/// Structure-of-arrays batch of particle-tool contacts for one tool and one step.
struct ContactBatch {
  std::size_t count = 0;
  double dt = 0.0;                          ///< s
  double stiffness = 0.0;                   ///< N/m, normal penalty stiffness k (eq. 10)
  const std::size_t* particle = nullptr;    ///< particle index of each contact
  const double* mass = nullptr;             ///< kg (inertial: mass scaling included)
  const double* normal = nullptr;           ///< 3 per contact, unit, pointing into the workpiece
  const double* normal_force = nullptr;     ///< N, >= 0 (magnitude of the penalty force, eq. 11)
  const double* penetration = nullptr;      ///< m, > 0 when touching (<= 0 only within wall_range())
  const double* normal_velocity = nullptr;  ///< m/s, (v - v_wall) . n (< 0: approaching)
  const double* damping = nullptr;          ///< N s/m, normal damping coefficient c_d = 2 zeta sqrt(k m)
  const double* tangential_velocity = nullptr;  ///< 3 per contact, particle minus wall, v - (v.n) n (m/s)
  /// 3 per contact: the particle's acceleration from every other force of the step (stress, body
  /// force), m/s^2 — what a sticking force must also cancel (eq. 18a).
  const double* acceleration = nullptr;
  const double* contact_area = nullptr;     ///< m^2, particle's share of the surface (dx^2)
  const double* yield_stress = nullptr;     ///< Pa, from the material (infinity if none)
  /// 3 per contact, IN/OUT: the law's per-contact memory (e.g. the tangential spring force of
  /// `coulomb`, N). Kept by the core per touching particle, by id, so it survives reordering
  /// (theory section 6); zero for a particle that was not touching at the last pass, forgotten when it
  /// leaves the contact; written to the outputs as friction_history_<tool>. Null unless needs_history().
  double* history = nullptr;
  double* tangential_force = nullptr;       ///< 3 per contact, OUT: force on the particle (N)
  /// OUT: 0 when the contact slides; 1 when it sticks (its friction heat |f_t| |v_t|, eq. 18e, is the
  /// slip the force removes within the step); kHeldOnWall when the law holds the particle on the
  /// wall whatever the force (kinematic sticking, eq. 18j): no slip, so no friction heat.
  double* sticking = nullptr;
};

/// ContactBatch::sticking value of a contact held on the wall kinematically (eq. 18j).
inline constexpr double kHeldOnWall = 2.0;

/// Tangential force that brings the relative tangential velocity to zero at the end of the step
/// with the leapfrog update v' = v + dt (a_other + f/m): f = -m (v_t / dt + a_other,t)
/// (docs/theory.md eq. 18a). Writes 3 components into f and returns |f|.
inline double sticking_force(const ContactBatch& b, std::size_t c, double* f) {
  const double* n = b.normal + 3 * c;
  const double* vt = b.tangential_velocity + 3 * c;
  double a[3] = {0.0, 0.0, 0.0};
  if (b.acceleration) {
    const double* ac = b.acceleration + 3 * c;
    const double an = ac[0] * n[0] + ac[1] * n[1] + ac[2] * n[2];
    for (int d = 0; d < 3; ++d) a[d] = ac[d] - an * n[d];  // tangential part only
  }
  const double m = b.mass[c], inv_dt = 1.0 / b.dt;
  double norm2 = 0.0;
  for (int d = 0; d < 3; ++d) {
    f[d] = -m * (vt[d] * inv_dt + a[d]);
    norm2 += f[d] * f[d];
  }
  return std::sqrt(norm2);
}

class ContactLaw {
 public:
  virtual ~ContactLaw() = default;
  /// True if the law needs the yield stress (the core then asks the material for it).
  virtual bool needs_yield_stress() const { return false; }
  /// True if the law keeps per-contact memory in ContactBatch::history (3 numbers per contact).
  virtual bool needs_history() const { return false; }
  /// Extra reach of the law beyond touching, as a fraction of dx: particles with
  /// dx/2 <= d < dx/2 + wall_range() dx join the batch with penetration g <= 0 and f_n = 0. For
  /// pressure-independent wall laws (Navier slip), whose wall-adjacent particles carry the wall
  /// shear even where they press on the wall with no force (docs/theory.md eq. 18i).
  virtual double wall_range() const { return 0.0; }
  virtual void tangential_forces(ContactBatch& batch) const = 0;
};

}  // namespace sphforge
