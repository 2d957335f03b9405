// The kernel of the pair loops (theory eqs. 1-2), shared by every pair pass of the mechanics
// (engine/sph_operators.cpp, engine/second_order_gradient.cpp): one place for its formulas.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "sphforge/kernels.hpp"

namespace sphforge {

#define SPHFORGE_PAIR_INLINE __attribute__((always_inline)) inline

// Instances of the pair loops. Each pair pass is a per-particle function (always inlined, its
// neighbour loop written for `omp simd`: scalar accumulators, no branches) that for_each_particle()
// below runs over all particles in the best instance the CPU has, chosen at run time:
//  - generic (x86-64 baseline SSE2, and every other architecture);
//  - AVX2 + FMA: four pairs per instruction;
//  - AVX-512VL at the same 256-bit width: 32 vector registers instead of 16 (the momentum loop keeps
//    about 30 per-particle constants and spilled them with 16) and mask registers for the kernel's
//    selects. 512-bit vectors were slower (docs/bench.md "Throughput").
// The summation order is fixed by the instance (its vector width, here 4 or 1), never by the
// number of threads.
#if defined(__GNUC__) && defined(__x86_64__)
#define SPHFORGE_TARGET_AVX2 __attribute__((target("avx2,fma")))
#define SPHFORGE_TARGET_AVX512VL \
  __attribute__((target("avx2,fma,avx512f,avx512vl,avx512dq,prefer-vector-width=256")))
#else
#define SPHFORGE_TARGET_AVX2
#define SPHFORGE_TARGET_AVX512VL
#endif

enum class PairLoopIsa { generic = 0, avx2 = 1, avx512vl = 2 };

/// The instance the pair loops run: the best the CPU has, capped by limit_pair_loop_isa()
/// (engine/sph_operators.hpp).
PairLoopIsa pair_loop_isa();

namespace pair_loop_detail {
// The same parallel loop compiled three times; `body` (an always-inline lambda) is inlined into
// each and vectorised for its instruction set.
template <class Body>
void run_generic(std::size_t n, const Body& body) {
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) body(i);
}
template <class Body>
SPHFORGE_TARGET_AVX2 void run_avx2(std::size_t n, const Body& body) {
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) body(i);
}
template <class Body>
SPHFORGE_TARGET_AVX512VL void run_avx512vl(std::size_t n, const Body& body) {
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) body(i);
}
}  // namespace pair_loop_detail

/// body(i) for every particle i in [0, n), OpenMP-parallel (dynamic chunks of 512 particles: the
/// cost per particle varies with its neighbours), in the instance of pair_loop_isa(). body must be
/// an always-inline lambda (SPHFORGE_PAIR_LAMBDA), so that its loops are compiled for each instance.
template <class Body>
void for_each_particle(std::size_t n, const Body& body) {
  switch (pair_loop_isa()) {
    case PairLoopIsa::avx512vl: pair_loop_detail::run_avx512vl(n, body); break;
    case PairLoopIsa::avx2: pair_loop_detail::run_avx2(n, body); break;
    default: pair_loop_detail::run_generic(n, body);
  }
}
#define SPHFORGE_PAIR_LAMBDA __attribute__((always_inline))

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
    shape(std::sqrt(r2) * inv_h, f_scale, w_scale, F, W);
  }
  /// F(r) of a pair whose smoothing length is h (variable spacing, eq. 138: h = h_ij), the same
  /// formula with its constants computed for this pair.
  SPHFORGE_PAIR_INLINE double factor_at(double r2, double h) const {
    double F, W;
    factor_and_value_at(r2, h, F, W);
    return F;
  }
  /// F(r) and W(r) of a pair with smoothing length h (eq. 138).
  SPHFORGE_PAIR_INLINE void factor_and_value_at(double r2, double h, double& F, double& W) const {
    const double ih = 1.0 / h;
    const double sigma =
        (K == KernelKind::WendlandC2 ? 21.0 / (16.0 * kernel_detail::kPi) : 1.0 / kernel_detail::kPi) * ih * ih * ih;
    shape(std::sqrt(r2) * ih, sigma * ih * ih, sigma, F, W);
  }

 private:
  /// F = f_scale f(q) and W = w_scale w(q), the kernel's shape at q = r / h (eqs. 1-2).
  static SPHFORGE_PAIR_INLINE void shape(double q, double f_scale, double w_scale, double& F, double& W) {
    if constexpr (K == KernelKind::WendlandC2) {
      const double t = std::max(0.0, 1.0 - 0.5 * q);
      const double t3 = t * t * t;
      F = f_scale * (-5.0) * t3;
      W = w_scale * t3 * t * (2.0 * q + 1.0);
    } else {
      const double t = std::max(0.0, 2.0 - q);
      const bool in = q < 1.0;
      F = f_scale * (in ? -3.0 + 2.25 * q : -0.75 * t * t / q);  // q = 0 only selects inner
      W = w_scale * (in ? 1.0 - 1.5 * q * q + 0.75 * q * q * q : 0.25 * t * t * t);
    }
  }
};

/// The smoothing length of a pair under variable spacing: the mean of the two particles' (eq. 138),
/// symmetric, so that W_ij = W_ji and grad_i W_ij = -grad_j W_ji (momentum conserved pair by pair).
SPHFORGE_PAIR_INLINE double pair_smoothing_length(double hi, double hj) { return 0.5 * (hi + hj); }

}  // namespace sphforge
