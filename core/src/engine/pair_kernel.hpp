// The kernel of the pair loops (theory eqs. 1-2), shared by every pair pass of the mechanics
// (engine/sph_operators.cpp, engine/second_order_gradient.cpp): one place for its formulas.
#pragma once

#include <algorithm>
#include <cmath>

#include "sphforge/kernels.hpp"

namespace sphforge {

#define SPHFORGE_PAIR_INLINE __attribute__((always_inline)) inline
// The AVX2 + FMA instances of the pair loops (engine/sph_operators.cpp explains the scheme).
#if defined(__GNUC__) && defined(__x86_64__)
#define SPHFORGE_TARGET_AVX2 __attribute__((target("avx2,fma")))
#else
#define SPHFORGE_TARGET_AVX2
#endif

/// True when the pair loops run their AVX2 + FMA instances: the CPU has them and
/// allow_avx2_pair_loops() (engine/sph_operators.hpp) has not turned them off.
bool pair_loops_use_avx2();

// Kernel gradient factor F = (dW/dr)/r and value W of one pair from r^2 (theory eqs. 1-2), without
// branches: the pair loops then run straight through (which of the kernel's pieces a pair falls
// in is unpredictable, and the lists include the Verlet skin, where both are 0). Same formulas
// as kernels.hpp with the constants hoisted out of the loop.
template <KernelKind K>
struct PairKernel {
  double inv_h, f_scale, w_scale;
  explicit PairKernel(double h) : inv_h(1.0 / h) {
    const double sigma = K == KernelKind::WendlandC2 ? wendland_c2_sigma(h) : cubic_spline_sigma(h);
    f_scale = sigma / (h * h);
    w_scale = sigma;
  }
  /// F(r), 0 beyond the support 2h.
  SPHFORGE_PAIR_INLINE double factor(double r2) const {
    const double q = std::sqrt(r2) * inv_h;
    if constexpr (K == KernelKind::WendlandC2) {
      const double t = std::max(0.0, 1.0 - 0.5 * q);
      return f_scale * (-5.0) * t * t * t;
    } else {
      const double t = std::max(0.0, 2.0 - q);
      const double inner = -3.0 + 2.25 * q, outer = -0.75 * t * t / q;  // q = 0 only selects inner
      return f_scale * (q < 1.0 ? inner : outer);
    }
  }
  /// F(r) and W(r), both 0 beyond the support.
  SPHFORGE_PAIR_INLINE void factor_and_value(double r2, double& F, double& W) const {
    const double q = std::sqrt(r2) * inv_h;
    if constexpr (K == KernelKind::WendlandC2) {
      const double t = std::max(0.0, 1.0 - 0.5 * q);
      const double t3 = t * t * t;
      F = f_scale * (-5.0) * t3;
      W = w_scale * t3 * t * (2.0 * q + 1.0);
    } else {
      const double t = std::max(0.0, 2.0 - q);
      const bool in = q < 1.0;
      F = f_scale * (in ? -3.0 + 2.25 * q : -0.75 * t * t / q);
      W = w_scale * (in ? 1.0 - 1.5 * q * q + 0.75 * q * q * q : 0.25 * t * t * t);
    }
  }
};

}  // namespace sphforge
