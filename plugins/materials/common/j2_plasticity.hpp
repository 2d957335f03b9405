// Shared pieces of the von Mises (J2) material plugins (elastoplastic, johnson_cook): the
// deviatoric elastic predictor, the von Mises stress, the linear equation of state and the
// radial return solved by a safeguarded Newton iteration. Each physics term lives here once;
// the plugins supply only their yield law. docs/theory.md section 5, eqs. 15-17 and 33-35.
#pragma once

#include <cmath>
#include <limits>

namespace sphforge::j2 {

/// Deviatoric elastic predictor S += 2 G dt (D - tr(D)/3 I), D = sym(L) (eq. 15). `s` holds the
/// Jaumann-rotated deviatoric stress (xx yy zz xy yz xz) on entry.
inline void elastic_predictor(const double* L, double two_g_dt, double* s) {
  const double tr3 = (L[0] + L[4] + L[8]) * (1.0 / 3.0);  // a product: a division costs ~4x more
  s[0] += two_g_dt * (L[0] - tr3);
  s[1] += two_g_dt * (L[4] - tr3);
  s[2] += two_g_dt * (L[8] - tr3);
  s[3] += two_g_dt * 0.5 * (L[1] + L[3]);
  s[4] += two_g_dt * 0.5 * (L[5] + L[7]);
  s[5] += two_g_dt * 0.5 * (L[2] + L[6]);
}

/// Von Mises equivalent stress q = sqrt(3/2 S:S) of a deviatoric stress (eq. 16).
inline double von_mises(const double* s) {
  const double ss = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
  return std::sqrt(1.5 * ss);
}

/// Isotropic moduli from Young's modulus and Poisson's ratio: G = E/(2(1 + nu)), K = E/(3(1 - 2 nu)) (eq. 33).
struct ElasticModuli {
  double bulk, shear;  ///< K, G (Pa)
};
inline ElasticModuli moduli_from_youngs(double youngs_modulus, double poisson_ratio) {
  return {youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio)), youngs_modulus / (2.0 * (1.0 + poisson_ratio))};
}

/// Linear equation of state p = K (rho/rho0 - 1) = K (rho - rho0) / rho0 (eq. 17), with 1/rho0
/// precomputed (no division per particle); written with rho - rho0 so that p = 0 exactly at rho0 (a
/// body at rest stays at rest to the bit: rho/rho0 - 1 by a product may round to +-1e-16).
inline double linear_pressure(double bulk_modulus, double density, double reference_density,
                              double inverse_reference_density) {
  return bulk_modulus * (density - reference_density) * inverse_reference_density;
}

/// Eq. 17 with isotropic thermal expansion (eq. 17a): the stress-free density of a particle dT above
/// the expansion's reference temperature is rho0 / (1 + 3 alpha dT), so
/// p = K (rho (1 + 3 alpha dT) / rho0 - 1). `volumetric_expansion` is 3 alpha (1/K). A J2 material's
/// thermal strain is volumetric only, so the pressure is the one place it enters.
inline double thermal_linear_pressure(double bulk_modulus, double density, double reference_density,
                                      double inverse_reference_density, double volumetric_expansion, double dT) {
  return bulk_modulus * (density * (1.0 + volumetric_expansion * dT) - reference_density) * inverse_reference_density;
}

/// Yield stress after a plastic increment d and its derivative d sigma_y / d d (Pa).
struct YieldValue {
  double stress;
  double slope;
};

struct ReturnResult {
  double d_eps_p = 0.0;       ///< plastic strain increment of the step (1)
  double yield_stress = 0.0;  ///< sigma_y at the returned state (Pa)
  int iterations = 0;
  bool converged = true;
};

/// Relative tolerance on the yield condition |q* - 3 G d - sigma_y(d)| <= tol sigma_y (eq. 34).
inline constexpr double kYieldTolerance = 1e-10;
/// Iteration cap: the safeguarded Newton converges in a handful of steps; bisection alone would
/// need about 35 halvings of the bracket to reach 1e-10, so 60 is a true failure, counted.
inline constexpr int kMaxIterations = 60;

/// Relative residual |g|/sigma_y below which the return asks the law for its curvature bound (eq. 34a).
inline constexpr double kBoundWorthIt = 1e-3;

/// Particles per block of the interleaved return below: enough independent Newton iterations in
/// flight to hide the latency of one (a logarithm, a power and a division in a dependent chain),
/// few enough that a block's trial states stay in L1 (a few kB on the stack).
inline constexpr int kReturnBlock = 32;

/// Radial returns (eq. 34) of up to kReturnBlock particles at once: for each lane k, solves
/// g_k(d) = q*_k - 3 G d - sigma_y,k(d) = 0 for the plastic increment d, given a trial state outside
/// the surface (g_k(0) > 0). The root lies in [0, q*/(3G)] (g there is -sigma_y <= 0 for any
/// non-negative yield law), so Newton with the analytic derivative g' = -3G - sigma_y' is kept inside
/// the bracket and falls back to bisection when a step would leave it (e.g. the infinite slope of
/// eps_p^n at eps_p = 0 for n < 1, or the kink of a cut-off rate term). Convergence is judged
/// relative to sigma_y (unit-free); when sigma_y = 0 (above the melting temperature) g is linear and
/// the first step is exact, judged against round-off of q*.
/// Accepting a step without evaluating it (eq. 34a): after the Newton step d -> d' the residual is
/// the Taylor remainder, |g(d')| <= M (d' - d)^2 / 2 with M >= |sigma_y''| between d and d', which
/// `yield.curvature_bound(k, y, d, d')` returns from the values already computed at d (infinity
/// where the law has no cheap bound). When that bound already meets the tolerance, d' is returned with
/// sigma_y = q* - 3 G d' (so the stress lies on the surface within the bound) and the evaluation that
/// would only have confirmed it is saved: one of three for Johnson-Cook, one of two for linear hardening.
/// Why lanes: one particle's iterations form a dependent chain whose latency, not arithmetic, sets
/// the cost; sweeping the still-unconverged lanes each iteration keeps several independent chains
/// in flight. Each lane's arithmetic is exactly that of a return on its own (same iterates, same
/// result bit for bit). The law works on whole lanes, so that it can batch its transcendental
/// functions: `yield.evaluate(n, lanes, d, y)` sets y[k] (with members `stress`, sigma_y, and `slope`,
/// d sigma_y / d d) for the n lanes k = lanes[0..n) at the increments d[k].
/// Returns the number of lanes that hit the iteration cap (`converged` false in `r`).
template <class YieldLaw>
inline int radial_returns(int count, const double* q_trial, const double* sigma_y0, double three_g,
                          const YieldLaw& yield, ReturnResult* r) {
  typename YieldLaw::Value y_of[kReturnBlock];
  double lo[kReturnBlock], hi[kReturnBlock], d[kReturnBlock], roundoff[kReturnBlock];
  int active[kReturnBlock];
  for (int k = 0; k < count; ++k) {
    lo[k] = 0.0;
    hi[k] = q_trial[k] / three_g;
    // First guess: the perfectly plastic increment; with hardening it overshoots (g <= 0 there).
    d[k] = (q_trial[k] - sigma_y0[k]) / three_g;
    roundoff[k] = 4.0 * std::numeric_limits<double>::epsilon() * q_trial[k];
    active[k] = k;
  }
  int n_active = count;
  for (int it = 1; it <= kMaxIterations && n_active > 0; ++it) {
    int still = 0;  // the unconverged lanes are compacted to the front of `active`
    yield.evaluate(n_active, active, d, y_of);
    for (int a = 0; a < n_active; ++a) {
      const int k = active[a];
      const auto& y = y_of[k];
      const double g = q_trial[k] - three_g * d[k] - y.stress;
      r[k].d_eps_p = d[k];
      r[k].yield_stress = y.stress;
      r[k].iterations = it;
      r[k].converged = true;
      if (std::abs(g) <= kYieldTolerance * y.stress || std::abs(g) <= roundoff[k]) continue;
      if (g > 0.0) lo[k] = d[k]; else hi[k] = d[k];
      const double next = d[k] + g / (three_g + y.slope);
      if (next > lo[k] && next < hi[k]) {
        // The bound is only worth its cost once the residual is small (far from the root the
        // remainder is never within 1e-10); skipping it is always safe: d' is then evaluated.
        const double step = next - d[k];
        const double remainder = std::abs(g) <= kBoundWorthIt * y.stress
                                     ? 0.5 * yield.curvature_bound(k, y, d[k], next) * step * step  // eq. 34a
                                     : std::numeric_limits<double>::infinity();
        const double sigma_next = q_trial[k] - three_g * next;  // = sigma_y(d') - g(d')
        if (remainder <= kYieldTolerance * (sigma_next - remainder)) {
          r[k].d_eps_p = next;
          r[k].yield_stress = sigma_next;
          continue;
        }
        d[k] = next;
      } else {
        d[k] = 0.5 * (lo[k] + hi[k]);
      }
      active[still++] = k;
    }
    n_active = still;
  }
  for (int a = 0; a < n_active; ++a) r[active[a]].converged = false;
  return n_active;
}

/// Scales the trial deviatoric stress back onto the surface: S = S* sigma_y / q* (eq. 35).
inline void scale_to_surface(double* s, double q_trial, double sigma_y) {
  const double f = sigma_y / q_trial;
  for (int c = 0; c < 6; ++c) s[c] *= f;
}

}  // namespace sphforge::j2
