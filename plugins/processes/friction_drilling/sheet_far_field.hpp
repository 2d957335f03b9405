// The sheet beyond the modelled disc, as heat sees it (docs/theory.md eq. 121b): the paper models a
// 10 mm disc clamped at its rim, but a real specimen is a larger sheet, and heat that reaches the
// disc's rim flows on into it. Here that sheet is a thin annulus R <= r <= R_far of the sheet's
// thickness: radial conduction only (the temperature uniform through the thickness), its faces and
// outer edge adiabatic, cut into finite volumes of width dr and stepped explicitly. It exchanges heat
// with the disc's outermost ring of particles, whose mean temperature it sees at their mean radius.
// Header-only so that the unit test (tests/unit/test_friction_drilling_far_field.cpp) can use it.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace sphforge::friction_drilling {

class SheetFarField {
 public:
  /// ring_radius: mean radius of the disc's outer particle ring (< R); R: the disc's edge, where the
  /// annulus starts; far_radius: its outer edge; thickness t; angle: the simulated sector (2 pi for
  /// the whole disc); k (W/(m K)) and rho_c (J/(m^3 K)) of the sheet; T0 its initial temperature; dr
  /// the target width of a volume (the last one takes the remainder).
  SheetFarField(double ring_radius, double R, double far_radius, double thickness, double angle, double k,
                double rho_c, double T0, double dr) {
    if (!(ring_radius > 0.0 && ring_radius < R && far_radius > R && thickness > 0.0 && angle > 0.0 && k > 0.0 &&
          rho_c > 0.0 && dr > 0.0))
      throw std::invalid_argument("SheetFarField: need 0 < ring radius < R < far radius and positive t, angle, k, rho c, dr");
    const int cells = std::max(1, static_cast<int>(std::ceil((far_radius - R) / dr - 1e-9)));
    std::vector<double> edges(cells + 1);
    for (int j = 0; j <= cells; ++j) edges[j] = std::min(far_radius, R + j * dr);
    T_.assign(cells, T0);
    capacity_.resize(cells);
    conductance_.resize(cells);  // conductance_[j]: between cell j and the one inside it (j = 0: the ring)
    double inner_centre = ring_radius;
    // A thin annulus of conductivity k, thickness t and angle a passes Q = k t a (T_in - T_out) / ln(r_out / r_in)
    // between two radii (steady radial conduction): exact for the link between two cell centres.
    for (int j = 0; j < cells; ++j) {
      const double centre = 0.5 * (edges[j] + edges[j + 1]);
      capacity_[j] = rho_c * thickness * 0.5 * angle * (edges[j + 1] * edges[j + 1] - edges[j] * edges[j]);
      conductance_[j] = k * thickness * angle / std::log(centre / inner_centre);
      inner_centre = centre;
    }
    // Explicit stability: each cell's capacity over its two conductances (the forward-Euler bound
    // C / sum G keeps every update a convex combination), with a margin of 2.
    stable_dt_ = std::numeric_limits<double>::infinity();
    for (int j = 0; j < cells; ++j) {
      const double g = conductance_[j] + (j + 1 < cells ? conductance_[j + 1] : 0.0);
      stable_dt_ = std::min(stable_dt_, 0.5 * capacity_[j] / g);
    }
  }

  /// Advances the annulus by dt (s, physical time) with the ring held at T_ring; returns the mean
  /// heat flow from the ring into the annulus over dt (W).
  double advance(double T_ring, double dt) {
    if (dt <= 0.0) return 0.0;
    const int substeps = static_cast<int>(std::ceil(dt / stable_dt_));
    const double tau = dt / substeps;
    const std::size_t cells = T_.size();
    flux_.resize(cells + 1);
    double heat_J = 0.0;
    for (int s = 0; s < substeps; ++s) {
      // flux_[j]: heat flow (W) into cell j from the inside; flux_[cells] = 0 (adiabatic outer edge).
      flux_[0] = conductance_[0] * (T_ring - T_[0]);
      for (std::size_t j = 1; j < cells; ++j) flux_[j] = conductance_[j] * (T_[j - 1] - T_[j]);
      flux_[cells] = 0.0;
      for (std::size_t j = 0; j < cells; ++j) T_[j] += tau * (flux_[j] - flux_[j + 1]) / capacity_[j];
      heat_J += tau * flux_[0];
    }
    absorbed_J_ += heat_J;
    return heat_J / dt;
  }

  const std::vector<double>& temperatures() const { return T_; }
  void set_temperatures(const std::vector<double>& T) {
    if (T.size() != T_.size()) throw std::invalid_argument("SheetFarField: saved state has another number of cells");
    T_ = T;
  }
  /// Heat taken from the ring since the start (J).
  double absorbed_J() const { return absorbed_J_; }
  void set_absorbed_J(double e) { absorbed_J_ = e; }
  /// Heat stored in the annulus above the uniform temperature T_ref (J).
  double stored_J(double T_ref) const {
    double e = 0.0;
    for (std::size_t j = 0; j < T_.size(); ++j) e += capacity_[j] * (T_[j] - T_ref);
    return e;
  }
  double stable_dt() const { return stable_dt_; }

 private:
  std::vector<double> T_, capacity_, conductance_, flux_;
  double stable_dt_ = 0.0, absorbed_J_ = 0.0;
};

}  // namespace sphforge::friction_drilling
