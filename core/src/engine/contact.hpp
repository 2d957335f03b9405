// Penalty contact between particles and rigid tools (theory eqs. 10-12). The normal force is a
// damped penalty spring; the tangential force comes from the tool's contact-law plugin, called
// once per tool with the whole batch of touching particles.
#pragma once

#include <cstddef>
#include <vector>

#include "sphforge/contact_law.hpp"
#include "sphforge/material.hpp"
#include "sphforge/tool.hpp"

namespace sphforge {

struct ContactSettings {
  double stiffness_factor = 1.0;  ///< kappa in k = kappa * M * dx (M: P-wave modulus rho0 c^2)
  double damping_ratio = 0.2;     ///< zeta: fraction of critical damping of the particle-spring
};

class PenaltyContact {
 public:
  /// Tangential (friction) law for each tool, same order as the tools.
  void configure(const ContactSettings& settings, std::vector<const ContactLaw*> laws, double spacing,
                 double p_wave_modulus);

  /// Spring stiffness k (N/m) of one particle against a wall.
  double stiffness() const { return stiffness_; }
  /// Largest stable step for a particle of mass m on the contact spring (theory eq. 12).
  double stable_time_step(double min_mass) const;

  /// Adds contact forces to `force` (N, 3 per particle), sets tool reactions, and returns the
  /// number of contacts. Reads x, v, mass. `yield` may be null when no law needs it.
  std::size_t apply(std::vector<RigidTool>& tools, const double* x, const double* v, const double* mass,
                    const double* yield, std::size_t n, double dt, double* force);

  /// Fraction of contacts that stuck in the last apply() (0 when none).
  double sticking_fraction() const { return sticking_fraction_; }
  /// Memory held by the scratch arrays (bytes).
  std::size_t bytes() const {
    std::size_t total = (distance_.capacity() + normal_.capacity()) * sizeof(double) +
                        particle_.capacity() * sizeof(std::size_t);
    for (const auto* b : {&batch_mass_, &batch_normal_, &batch_fn_, &batch_gap_, &batch_vt_, &batch_area_,
                          &batch_yield_, &batch_ft_, &batch_stick_, &batch_vwall_})
      total += b->capacity() * sizeof(double);
    return total;
  }

 private:
  ContactSettings settings_;
  std::vector<const ContactLaw*> laws_;
  double spacing_ = 0.0, stiffness_ = 0.0;
  double sticking_fraction_ = 0.0;
  // Scratch, kept between steps so that the pass does not allocate once warmed up.
  std::vector<double> distance_, normal_;
  std::vector<std::size_t> particle_;
  std::vector<double> batch_mass_, batch_normal_, batch_fn_, batch_gap_, batch_vt_, batch_area_, batch_yield_,
      batch_ft_, batch_stick_, batch_vwall_;
};

}  // namespace sphforge
