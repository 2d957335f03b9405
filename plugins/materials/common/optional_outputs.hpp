// Output fields of the J2 material plugins. `plastic_strain` is state (always allocated); the
// plastic strain rate, von Mises stress and yield stress are diagnostics, allocated only when the
// case lists them in the material's "output_fields" (docs/theory.md section 5).
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "sphforge/errors.hpp"
#include "sphforge/fields.hpp"
#include "sphforge/material.hpp"
#include "sphforge/parameters.hpp"
#include "j2_plasticity.hpp"

namespace sphforge::j2 {

namespace output {
inline constexpr const char* plastic_strain_rate = "plastic_strain_rate";  // 1/s, physical (rate / f)
inline constexpr const char* yield_stress = "yield_stress";                // Pa
}  // namespace output

class OptionalOutputs {
 public:
  static ParamSpec spec() {
    return ParamSpec::array("output_fields",
                            "diagnostic fields to allocate and write: any of \"plastic_strain_rate\", "
                            "\"von_mises_stress\", \"yield_stress\" (plastic_strain is always there)");
  }

  explicit OptionalOutputs(const ParamValues& p) {
    if (!p.has("output_fields")) return;
    const json& list = p.raw("output_fields");
    if (list.is_null()) return;
    if (!list.is_array()) p.fail("output_fields", "expected an array of field names");
    static const std::vector<std::string> allowed = {output::plastic_strain_rate, field::von_mises_stress,
                                                     output::yield_stress};
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::string where = p.pointer_of("output_fields") + "/" + std::to_string(k);
      if (!list[k].is_string()) throw InputError(p.file(), where, "expected a field name (string)");
      const std::string name = list[k].get<std::string>();
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
        throw InputError(p.file(), where,
                         "unknown output field '" + name + "' (expected plastic_strain_rate, von_mises_stress or yield_stress)");
      if (name == output::plastic_strain_rate) rate_ = true;
      if (name == field::von_mises_stress) von_mises_ = true;
      if (name == output::yield_stress) yield_ = true;
    }
  }

  std::vector<FieldInfo> fields() const {
    std::vector<FieldInfo> f = {{field::plastic_strain, 1, "1"}};
    if (rate_) f.push_back({output::plastic_strain_rate, 1, "1/s"});
    if (von_mises_) f.push_back({field::von_mises_stress, 1, "Pa"});
    if (yield_) f.push_back({output::yield_stress, 1, "Pa"});
    return f;
  }

  /// The batch's arrays, offset to its first particle; null for outputs not requested.
  struct Arrays {
    double* plastic_strain = nullptr;
    double* plastic_strain_rate = nullptr;
    double* von_mises_stress = nullptr;
    double* yield_stress = nullptr;
  };
  Arrays arrays(MaterialBatch& b) const {
    Arrays a;
    a.plastic_strain = b.fields->f64(field::plastic_strain) + b.first;
    if (rate_) a.plastic_strain_rate = b.fields->f64(output::plastic_strain_rate) + b.first;
    if (von_mises_) a.von_mises_stress = b.fields->f64(field::von_mises_stress) + b.first;
    if (yield_) a.yield_stress = b.fields->f64(output::yield_stress) + b.first;
    return a;
  }

 private:
  bool rate_ = false, von_mises_ = false, yield_ = false;
};

/// The trial states of one block of at most kReturnBlock consecutive particles that lie
/// outside the yield surface: the lanes of the interleaved return (eq. 34). A plugin adds its own
/// per-lane data (e.g. the thermal factor) in arrays indexed by the same lane.
struct PlasticLanes {
  int count = 0;
  std::size_t particle[kReturnBlock];  ///< index in the batch
  double q[kReturnBlock];              ///< trial von Mises stress (Pa)
  double eps[kReturnBlock];            ///< plastic strain at the start of the step
  double yield0[kReturnBlock];         ///< yield stress at zero plastic increment (Pa)
  int add(std::size_t i, double q_trial, double eps_p, double yield) {
    particle[count] = i;
    q[count] = q_trial;
    eps[count] = eps_p;
    yield0[count] = yield;
    return count++;
  }
};

/// The outputs of a particle whose trial state is inside the surface (elastic step): no plastic rate,
/// the trial von Mises stress, the yield stress at zero increment.
inline void elastic_outputs(const OptionalOutputs::Arrays& out, std::size_t i, double q, double yield) {
  if (out.plastic_strain_rate) out.plastic_strain_rate[i] = 0.0;
  if (out.von_mises_stress) out.von_mises_stress[i] = std::min(q, yield);
  if (out.yield_stress) out.yield_stress[i] = yield;
}

/// The plastic part of the stress update of a block's plastic lanes, common to every J2 material: the
/// Newton returns with `yield_at(k, d)` (eq. 34), the scaling onto the surface (eq. 35), the plastic
/// strain, the plastic heat beta sigma_y epsdot_p per unit mass (eq. 37); then the optional outputs.
/// The particles' deviatoric stresses hold their trial values on entry. Returns the number of
/// returns that hit the iteration cap.
template <class YieldAt>
inline int plastic_correction(const MaterialBatch& b, const OptionalOutputs::Arrays& out, const PlasticLanes& lanes,
                              double three_g, double inv_dt, double beta, const YieldAt& yield_at) {
  ReturnResult r[kReturnBlock];
  const int failed = radial_returns(lanes.count, lanes.q, lanes.yield0, three_g, yield_at, r);  // eq. 34
  for (int k = 0; k < lanes.count; ++k) {
    const std::size_t i = lanes.particle[k];
    const double sigma_y = r[k].yield_stress, rate = r[k].d_eps_p * inv_dt;
    scale_to_surface(b.deviatoric_stress + 6 * i, lanes.q[k], sigma_y);  // eq. 35
    out.plastic_strain[i] = lanes.eps[k] + r[k].d_eps_p;
    if (b.heat_source) b.heat_source[i] += beta * sigma_y * rate / b.density[i];  // eq. 37
    if (out.plastic_strain_rate) out.plastic_strain_rate[i] = rate / b.time_scaling;
    if (out.von_mises_stress) out.von_mises_stress[i] = sigma_y;
    if (out.yield_stress) out.yield_stress[i] = sigma_y;
  }
  return failed;
}

}  // namespace sphforge::j2
