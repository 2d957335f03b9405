// Failure criterion of the J2 material plugins (docs/failure.md, docs/theory.md section 16): the
// material owns the criterion, a particle fails once its equivalent plastic strain reaches
// `failure_plastic_strain` (eq. 110), and the core's bond rule (core/src/engine/bond_failure.hpp,
// eq. 112) then lets pairs of failed particles separate under tension. A material without the
// parameter declares no `failed` field, and the scene pays nothing.
#pragma once

#include <vector>

#include "sphforge/fields.hpp"
#include "sphforge/material.hpp"
#include "sphforge/parameters.hpp"

namespace sphforge::j2 {

class FailureCriterion {
 public:
  static ParamSpec spec() {
    return ParamSpec::number("failure_plastic_strain", "1", 0.0,
                             "equivalent plastic strain at which a particle fails: pairs of failed particles separate "
                             "under tension (docs/failure.md); 0: no failure",
                             0.0);
  }

  explicit FailureCriterion(const ParamValues& p) : strain_(p.number("failure_plastic_strain")) {}

  bool active() const { return strain_ > 0.0; }
  double strain() const { return strain_; }

  /// The `failed` field (1 per particle), only when the criterion is active.
  void add_fields(std::vector<FieldInfo>& f) const {
    if (active()) f.push_back({field::failed, 1, "1"});
  }

  /// failed_i = 1 once eps_p,i >= eps_f (eq. 110). The plastic strain never decreases, so the flag,
  /// and with it every broken bond, stays set once set (bond memory without a per-pair store).
  void update(const MaterialBatch& b, const double* plastic_strain) const {
    if (!active()) return;
    double* failed = b.fields->f64(field::failed) + b.first;
    const double eps_f = strain_;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < b.count; ++i)
      if (plastic_strain[i] >= eps_f) failed[i] = 1.0;
  }

 private:
  double strain_ = 0.0;
};

}  // namespace sphforge::j2
