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
  const double tr3 = (L[0] + L[4] + L[8]) / 3.0;
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

/// Linear equation of state p = K (rho/rho0 - 1) (eq. 17).
inline double linear_pressure(double bulk_modulus, double density, double reference_density) {
  return bulk_modulus * (density / reference_density - 1.0);
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

/// Radial return (eq. 34): solves g(d) = q* - 3 G d - sigma_y(d) = 0 for the plastic increment d,
/// given a trial state outside the surface (g(0) > 0). The root lies in [0, q*/(3G)] (g there is
/// -sigma_y <= 0 for any non-negative yield law), so Newton with the analytic derivative
/// g' = -3G - sigma_y' is kept inside the bracket and falls back to bisection when a step would
/// leave it (e.g. the infinite slope of eps_p^n at eps_p = 0 for n < 1, or the kink of a cut-off
/// rate term). Convergence is judged relative to sigma_y (unit-free); when sigma_y = 0 (above the
/// melting temperature) g is linear and the first step is exact, judged against round-off of q*.
/// `yield(d)` returns sigma_y and its slope at the increment d.
template <class YieldLaw>
inline ReturnResult radial_return(double q_trial, double three_g, const YieldLaw& yield, double sigma_y0) {
  ReturnResult r;
  double lo = 0.0, hi = q_trial / three_g;
  // First guess: the perfectly plastic increment; with hardening it overshoots (g <= 0 there).
  double d = (q_trial - sigma_y0) / three_g;
  const double roundoff = 4.0 * std::numeric_limits<double>::epsilon() * q_trial;
  for (int it = 1; it <= kMaxIterations; ++it) {
    const YieldValue y = yield(d);
    const double g = q_trial - three_g * d - y.stress;
    r.d_eps_p = d;
    r.yield_stress = y.stress;
    r.iterations = it;
    if (std::abs(g) <= kYieldTolerance * y.stress || std::abs(g) <= roundoff) return r;
    if (g > 0.0) lo = d; else hi = d;
    const double next = d + g / (three_g + y.slope);
    d = (next > lo && next < hi) ? next : 0.5 * (lo + hi);
  }
  r.converged = false;
  return r;
}

/// Scales the trial deviatoric stress back onto the surface: S = S* sigma_y / q* (eq. 35).
inline void scale_to_surface(double* s, double q_trial, double sigma_y) {
  const double f = sigma_y / q_trial;
  for (int c = 0; c < 6; ++c) s[c] *= f;
}

}  // namespace sphforge::j2
