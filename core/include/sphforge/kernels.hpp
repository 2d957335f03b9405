// SPH smoothing kernels W(r, h), shared by the CPU and CUDA backends (see hd.hpp).
//
// Conventions used by every kernel here:
//   r >= 0   distance between two particles  |x_i - x_j|          [m]
//   h > 0    smoothing length                                        [m]
//   q = r/h  normalised distance
//   support  both kernels vanish for q >= 2, i.e. the support radius is 2h (kernel_support_radius)
//   3D normalisation: integral over R^3 of W(|x|, h) dx = 1, i.e. int_0^{2h} 4 pi r^2 W(r, h) dr = 1
//   (tests/unit/test_kernels.cpp checks this numerically, together with the derivatives).
//
// The kernel gradient used by the SPH operators is
//   grad_i W_ij = (dW/dr)(r_ij, h) * (x_i - x_j) / r_ij = kernel_gradient_factor(r_ij, h) * (x_i - x_j),
// so the pair loops need F(r, h) = (dW/dr)/r. It is evaluated here in closed form (the factor 1/r is
// cancelled analytically), so it is finite at r = 0 (coincident particles) and needs no branch on r.
//
// Precision: all functions take and return double (state is double, DESIGN.md "Backends").
#pragma once

#include "sphforge/hd.hpp"

namespace sphforge {

/// Which smoothing kernel a case uses ("kernel": "cubic_spline" | "wendland_c2").
enum class KernelKind : int { CubicSpline = 0, WendlandC2 = 1 };

namespace kernel_detail {
inline constexpr double kPi = 3.14159265358979323846;
}  // namespace kernel_detail

/// Radius beyond which every kernel here is exactly zero: 2h.
SPH_HD SPH_INLINE constexpr double kernel_support_radius(double h) { return 2.0 * h; }

// ---------------------------------------------------------------------------------------------------
// Cubic spline (M4 B-spline), Monaghan 1992, "Smoothed particle hydrodynamics", Annu. Rev. Astron.
// Astrophys. 30:543-574, in 3D:
//
//   W(r, h) = sigma3 * { 1 - 3/2 q^2 + 3/4 q^3     0 <= q < 1
//                      { 1/4 (2 - q)^3             1 <= q < 2
//                      { 0                         q >= 2
//   sigma3  = 1 / (pi h^3)
//
//   dW/dr   = sigma3 / h * { -3 q + 9/4 q^2          0 <= q < 1
//                          { -3/4 (2 - q)^2         1 <= q < 2
//                          { 0                      q >= 2
//
//   (dW/dr)/r = sigma3 / h^2 * { -3 + 9/4 q           0 <= q < 1
//                              { -3/4 (2 - q)^2 / q   1 <= q < 2   (q >= 1 here: no division by 0)
//                              { 0                    q >= 2
//
// W is C2 at q = 1 (value 1/4, slope -3/4, curvature 3/2 from both sides) and at q = 2.
// ---------------------------------------------------------------------------------------------------

/// 3D normalisation of the cubic spline: 1/(pi h^3).
SPH_HD SPH_INLINE double cubic_spline_sigma(double h) {
  return 1.0 / (kernel_detail::kPi * h * h * h);
}

/// Cubic spline value W(r, h) [1/m^3].
SPH_HD SPH_INLINE double cubic_spline_value(double r, double h) {
  const double q = r / h;
  const double s = cubic_spline_sigma(h);
  if (q < 1.0) return s * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return s * 0.25 * t * t * t;
  }
  return 0.0;
}

/// Cubic spline radial derivative dW/dr [1/m^4].
SPH_HD SPH_INLINE double cubic_spline_derivative(double r, double h) {
  const double q = r / h;
  const double s = cubic_spline_sigma(h) / h;
  if (q < 1.0) return s * (-3.0 * q + 2.25 * q * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return s * (-0.75 * t * t);
  }
  return 0.0;
}

/// Cubic spline (dW/dr)/r [1/m^5]; finite at r = 0 where it equals -3 sigma3 / h^2.
SPH_HD SPH_INLINE double cubic_spline_gradient_factor(double r, double h) {
  const double q = r / h;
  const double s = cubic_spline_sigma(h) / (h * h);
  if (q < 1.0) return s * (-3.0 + 2.25 * q);
  if (q < 2.0) {
    const double t = 2.0 - q;
    return s * (-0.75 * t * t / q);
  }
  return 0.0;
}

// ---------------------------------------------------------------------------------------------------
// Wendland C2, Wendland 1995 (Adv. Comput. Math. 4:389-396), psi_{3,1}, with its support scaled to 2h
// as in DualSPHysics (Crespo et al. 2015, Comput. Phys. Commun. 187:204), in 3D:
//
//   W(r, h) = sigma3 * (1 - q/2)^4 (2 q + 1)          0 <= q < 2,   0 for q >= 2
//   sigma3  = 21 / (16 pi h^3)
//
//   dW/dr   = sigma3 / h * (-5 q) (1 - q/2)^3          0 <= q < 2
//   (dW/dr)/r = sigma3 / h^2 * (-5) (1 - q/2)^3         0 <= q < 2   (finite at r = 0: -5 sigma3/h^2)
//
// Positive-definite Fourier transform, hence no pairing instability (Dehnen & Aly 2012).
// ---------------------------------------------------------------------------------------------------

/// 3D normalisation of Wendland C2 with support 2h: 21/(16 pi h^3).
SPH_HD SPH_INLINE double wendland_c2_sigma(double h) {
  return 21.0 / (16.0 * kernel_detail::kPi * h * h * h);
}

/// Wendland C2 value W(r, h) [1/m^3].
SPH_HD SPH_INLINE double wendland_c2_value(double r, double h) {
  const double q = r / h;
  if (q >= 2.0) return 0.0;
  const double t = 1.0 - 0.5 * q;
  const double t2 = t * t;
  return wendland_c2_sigma(h) * t2 * t2 * (2.0 * q + 1.0);
}

/// Wendland C2 radial derivative dW/dr [1/m^4].
SPH_HD SPH_INLINE double wendland_c2_derivative(double r, double h) {
  const double q = r / h;
  if (q >= 2.0) return 0.0;
  const double t = 1.0 - 0.5 * q;
  return wendland_c2_sigma(h) / h * (-5.0 * q) * t * t * t;
}

/// Wendland C2 (dW/dr)/r [1/m^5]; finite at r = 0 where it equals -5 sigma3 / h^2.
SPH_HD SPH_INLINE double wendland_c2_gradient_factor(double r, double h) {
  const double q = r / h;
  if (q >= 2.0) return 0.0;
  const double t = 1.0 - 0.5 * q;
  return wendland_c2_sigma(h) / (h * h) * (-5.0) * t * t * t;
}

// ---------------------------------------------------------------------------------------------------
// Dispatch on the kernel chosen by the case. Pair loops that care about the branch should hoist the
// switch out of the loop (template on the kind, or call the specific function directly).
// ---------------------------------------------------------------------------------------------------

/// W(r, h) of `kind` [1/m^3].
SPH_HD SPH_INLINE double kernel_value(KernelKind kind, double r, double h) {
  return kind == KernelKind::WendlandC2 ? wendland_c2_value(r, h) : cubic_spline_value(r, h);
}

/// dW/dr of `kind` [1/m^4].
SPH_HD SPH_INLINE double kernel_derivative(KernelKind kind, double r, double h) {
  return kind == KernelKind::WendlandC2 ? wendland_c2_derivative(r, h)
                                        : cubic_spline_derivative(r, h);
}

/// (dW/dr)/r of `kind` [1/m^5], safe at r = 0; grad_i W_ij = factor * (x_i - x_j).
SPH_HD SPH_INLINE double kernel_gradient_factor(KernelKind kind, double r, double h) {
  return kind == KernelKind::WendlandC2 ? wendland_c2_gradient_factor(r, h)
                                        : cubic_spline_gradient_factor(r, h);
}

}  // namespace sphforge
