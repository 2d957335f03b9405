#include "engine/sph_operators.hpp"

#include "engine/pair_kernel.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

namespace sphforge {

namespace {
// Symmetric 6-component storage (xx yy zz xy yz xz) <-> 3x3 index.
constexpr int kSym[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};

// Each pair pass is a per-particle function (always inlined) that for_each_particle()
// (engine/pair_kernel.hpp) runs over all particles in the best instance the CPU has.
std::atomic<int> g_isa_limit{static_cast<int>(PairLoopIsa::avx512vl)};
#define SPHFORGE_ALWAYS_INLINE __attribute__((always_inline)) inline


struct GradientArgs {
  const NeighbourList* nl;
  const double *x, *v, *volume;
  double *L, *condition, *correction;
  std::size_t n;
  BondFailure failure;  // failed == null: no failure in the scene
  const double* h_point;  // per-particle smoothing length (variable spacing, eq. 138); null: uniform
};

// Failure: the loops with the bond rule of eq. 112 are separate instances, so that a scene without
// failure runs exactly the loops it ran before (no load, no multiplication, no branch).
// Variable: the pair's smoothing length is h_ij of eq. 138 (variable spacing), a separate instance
// so that a scene of one spacing runs the loop with the kernel's constants hoisted.
template <KernelKind K, bool Corrected, bool Failure, bool Variable>
SPHFORGE_ALWAYS_INLINE void velocity_gradient_particle(const GradientArgs& g, const PairKernel<K>& kernel,
                                                       std::size_t i) {
  const double* x = g.x;
  const double* v = g.v;
  const double* volume = g.volume;
  // Scalar accumulators, so that the neighbour loop vectorises (omp simd reduction).
  double l0 = 0, l1 = 0, l2 = 0, l3 = 0, l4 = 0, l5 = 0, l6 = 0, l7 = 0, l8 = 0;
  // M_i = -sum_j V_j x_ij (x) grad_i W_ij (eq. 3a), symmetric: xx yy zz xy yz xz
  double m0 = 0, m1 = 0, m2 = 0, m3 = 0, m4 = 0, m5 = 0;
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const double vi0 = v[3 * i], vi1 = v[3 * i + 1], vi2 = v[3 * i + 2];
  DecodedList list(*g.nl, i);
  const std::uint32_t* const nb = list.indices;
  const std::ptrdiff_t count = list.count;
  const BondRule<Failure> bond(g.failure, i);
  const double* hp = g.h_point;
  const double hi = Variable ? hp[i] : 0.0;
#pragma omp simd reduction(+ : l0, l1, l2, l3, l4, l5, l6, l7, l8, m0, m1, m2, m3, m4, m5)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const std::size_t j = nb[k];
    const double x0 = xi0 - x[3 * j], x1 = xi1 - x[3 * j + 1], x2 = xi2 - x[3 * j + 2];
    const double r2 = x0 * x0 + x1 * x1 + x2 * x2;
    double kf;
    if constexpr (Variable) kf = kernel.factor_at(r2, pair_smoothing_length(hi, hp[j]));
    else kf = kernel.factor(r2);
    double f = kf * volume[j];  // V_j (dW/dr)/r; 0 beyond the support
    // A broken bond under tension leaves the gradient and the correction matrix alike (eq. 113):
    // the particle then sees its side of the crack as a free surface.
    if constexpr (Failure)
      f *= bond.factor(j, x0, x1, x2);
    const double d0 = (v[3 * j] - vi0) * f, d1 = (v[3 * j + 1] - vi1) * f, d2 = (v[3 * j + 2] - vi2) * f;
    l0 += d0 * x0, l1 += d0 * x1, l2 += d0 * x2;
    l3 += d1 * x0, l4 += d1 * x1, l5 += d1 * x2;
    l6 += d2 * x0, l7 += d2 * x1, l8 += d2 * x2;
    if constexpr (Corrected) {
      const double f0 = f * x0, f1 = f * x1, f2 = f * x2;
      m0 -= f0 * x0, m1 -= f1 * x1, m2 -= f2 * x2;
      m3 -= f0 * x1, m4 -= f1 * x2, m5 -= f0 * x2;
    }
  }
  double l[9] = {l0, l1, l2, l3, l4, l5, l6, l7, l8};
  double* out = g.L + 9 * i;
  if constexpr (Corrected) {
    // Corrected gradient L = G M^-1 (eq. 3b), exact for linear fields also where the
    // neighbourhood is truncated (walls, free surfaces). M is dimensionless (I on a full,
    // regular neighbourhood), so its conditioning can be judged without units: where
    // det M <= 1e-3 or cond(M) = |M|_F |M^-1|_F >= 1000, too few neighbours span some direction
    // and the uncorrected gradient (M = I) is used instead. (Conditions of 30-160 are accepted and
    // occur at the ram face of thin paste billets: docs/validation/ram_extrusion.md, section 2b.)
    const double mom6[6] = {m0, m1, m2, m3, m4, m5};
    double mom[9];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) mom[3 * a + b] = mom6[kSym[a][b]];
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> G(l), M(mom);
    const double det = M.determinant();
    if (det > 1e-3) {
      const Eigen::Matrix3d Minv = M.inverse();
      const double cond = M.norm() * Minv.norm();
      if (cond < 1000.0) {
        const Eigen::Matrix3d corrected = G * Minv;
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> result(out);
        result = corrected;
        if (g.condition) g.condition[i] = cond;
        if (g.correction) {
          // C = M^-1 (symmetric, as M is), for the momentum equation (eq. 7)
          double* c = g.correction + 6 * i;
          c[0] = Minv(0, 0), c[1] = Minv(1, 1), c[2] = Minv(2, 2);
          c[3] = 0.5 * (Minv(0, 1) + Minv(1, 0)), c[4] = 0.5 * (Minv(1, 2) + Minv(2, 1));
          c[5] = 0.5 * (Minv(0, 2) + Minv(2, 0));
        }
        return;
      }
    }
    if (g.condition) g.condition[i] = -1.0;  // fallback used
    if (g.correction) {
      double* c = g.correction + 6 * i;
      c[0] = c[1] = c[2] = 1.0;
      c[3] = c[4] = c[5] = 0.0;
    }
  }
  for (int c = 0; c < 9; ++c) out[c] = l[c];
}

template <KernelKind K, bool Corrected, bool Failure, bool Variable>
void velocity_gradient_run(const GradientArgs& g, double h) {
  const PairKernel<K> kernel(h);
  for_each_particle(g.n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
    if (Failure && g.failure.failed[i] != 0.0)
      velocity_gradient_particle<K, Corrected, Failure, Variable>(g, kernel, i);
    else  // an intact particle has no broken bond (eq. 111)
      velocity_gradient_particle<K, Corrected, false, Variable>(g, kernel, i);
  });
}

template <KernelKind K, bool Corrected>
void velocity_gradient_impl(const NeighbourList& nl, double h, const double* x, const double* v,
                            const double* volume, double* L, std::size_t n, double* condition, double* correction,
                            const BondFailure& failure, const double* h_point) {
  const GradientArgs g{&nl, x, v, volume, L, condition, correction, n, failure, h_point};
  if (h_point) {
    if (failure.failed) velocity_gradient_run<K, Corrected, true, true>(g, h);
    else velocity_gradient_run<K, Corrected, false, true>(g, h);
  } else {
    if (failure.failed) velocity_gradient_run<K, Corrected, true, false>(g, h);
    else velocity_gradient_run<K, Corrected, false, false>(g, h);
  }
}

struct MomentumArgs {
  const NeighbourList* nl;
  const double *x, *v, *m, *rho, *volume, *stress_c, *R;
  const std::uint64_t* tension;  // mark_tension() of R; null: every particle may be under tension
  double* acc;
  std::size_t n;
  double h, eta2h2, alpha_c, beta, inv_w_dx, exponent;
  BondFailure failure;  // failed == null: no failure in the scene
  // Variable spacing (eq. 138): per-particle smoothing length, eta^2, and 1 / W(dx / h = 1 / kappa)
  // of a kernel with h = 1 (W(dx_ij, h_ij) = that / h_ij^3, eq. 139). h_point null: uniform.
  const double* h_point;
  double eta2, inv_w_dx_unit;
};

/// The sums of eq. 7 for particle i over its decoded neighbours nb[0, count).
/// Exponent: 0 without artificial stress, 4 for the usual n = 4 (multiplications), -1 for any
/// other n (pow). Failure: the bond rule of eq. 112 (a separate instance, see the gradient).
template <KernelKind K, int Exponent, bool Failure, bool Variable>
SPHFORGE_ALWAYS_INLINE void momentum_sums(const MomentumArgs& g, const PairKernel<K>& kernel, std::size_t i,
                                          const std::uint32_t* const nb, const std::ptrdiff_t count) {
  constexpr bool kStress = Exponent != 0;
  const double* x = g.x;
  const double* v = g.v;
  const double* m = g.m;
  const double* rho = g.rho;
  const double* volume = g.volume;
  const double* stress_c = g.stress_c;
  const double* R = g.R;
  const double h = g.h, eta2h2 = g.eta2h2, alpha_c = g.alpha_c, beta = g.beta;
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const double vi0 = v[3 * i], vi1 = v[3 * i + 1], vi2 = v[3 * i + 2];
  // 1/rho_i from the volume the corrected gradient used (V_i / m_i), for energy consistency.
  const double rhoi = rho[i], inv_rhoi = volume[i] / m[i];
  double ai[9], Ri[6];
  for (int c = 0; c < 9; ++c) ai[c] = stress_c[9 * i + c];
  for (int c = 0; c < 6; ++c) Ri[c] = kStress ? R[6 * i + c] : 0.0;
  double a0 = 0, a1 = 0, a2 = 0;
  const BondRule<Failure> bond(g.failure, i);
  const double* hp = g.h_point;
  const double hi = Variable ? hp[i] : 0.0;
#pragma omp simd reduction(+ : a0, a1, a2)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const std::size_t j = nb[k];
    const double x0 = xi0 - x[3 * j], x1 = xi1 - x[3 * j + 1], x2 = xi2 - x[3 * j + 2];
    const double r2 = x0 * x0 + x1 * x1 + x2 * x2;
    // grad_i W_ij = gw * x_ij. Pairs in the Verlet skin (gw = 0) run through too and add an
    // exact 0: cheaper than an unpredictable branch.
    double gw, w = 0.0;
    const double hij = Variable ? pair_smoothing_length(hi, hp[j]) : h;
    if constexpr (Variable) {
      if constexpr (kStress) kernel.factor_and_value_at(r2, hij, gw, w);
      else gw = kernel.factor_at(r2, hij);
    } else {
      if constexpr (kStress) kernel.factor_and_value(r2, gw, w);
      else gw = kernel.factor(r2);
    }
    // Stress term (eq. 7): V_j / rho_i (sigma_i C_i + sigma_j C_j) . grad_i W_ij, A = sigma C.
    const double* aj = stress_c + 9 * j;
    double a[9];
    for (int c = 0; c < 9; ++c) a[c] = ai[c] + aj[c];
    double vg = volume[j] * gw * inv_rhoi;
    // k_ij of eq. 112: a broken bond under tension carries no stress (eq. 114), the same pairs the
    // velocity gradient left out (energy consistency, eq. 113).
    double keep = 1.0;
    if constexpr (Failure) {
      keep = bond.factor(j, x0, x1, x2);
      vg *= keep;
    }
    a0 += vg * (a[0] * x0 + a[1] * x1 + a[2] * x2);
    a1 += vg * (a[3] * x0 + a[4] * x1 + a[5] * x2);
    a2 += vg * (a[6] * x0 + a[7] * x1 + a[8] * x2);
    // Stabilising terms, both central (along x_ij, so they exert no torque on the pair):
    // s_ij m_j grad_i W_ij with s_ij = artificial stress minus viscosity.
    double s = 0.0;
    if constexpr (kStress) {
      // Artificial stress projected on the pair direction (eq. 9):
      // f_ij^n e_ij . (R_i + R_j) . e_ij, f_ij = W(r_ij)/W(dx), e_ij = x_ij / r_ij. R is zero for
      // particles under no principal tension, and then this adds an exact 0.
      const double fw = Variable ? w * (hij * hij * hij) * g.inv_w_dx_unit : w * g.inv_w_dx;  // eq. 139
      double f;
      if constexpr (Exponent == 4) {
        const double fw2 = fw * fw;
        f = fw2 * fw2;
      } else {
        f = std::pow(fw, g.exponent);
      }
      // R_j is indexed as R[6 j + c], not through a pointer R + 6 j: GCC 12 turns only the former into
      // gathers, and with the pointer it left this whole loop scalar (docs/bench.md "Throughput").
      const double q = (Ri[0] + R[6 * j]) * x0 * x0 + (Ri[1] + R[6 * j + 1]) * x1 * x1 +
                       (Ri[2] + R[6 * j + 2]) * x2 * x2 +
                       2.0 * ((Ri[3] + R[6 * j + 3]) * x0 * x1 + (Ri[4] + R[6 * j + 4]) * x1 * x2 +
                              (Ri[5] + R[6 * j + 5]) * x0 * x2);
      // r2 > 0 for distinct particles; the floor only keeps coincident ones (f = 1, gw = 0) finite.
      s = f * q / std::max(r2, 1e-300);
      if constexpr (Failure) s *= keep;  // nor the artificial stress (eq. 114)
    }
    // Monaghan artificial viscosity, only for approaching pairs  (eq. 8)
    const double vij_xij = (vi0 - v[3 * j]) * x0 + (vi1 - v[3 * j + 1]) * x1 + (vi2 - v[3 * j + 2]) * x2;
    const double mu = Variable ? hij * std::min(vij_xij, 0.0) / (r2 + g.eta2 * hij * hij)
                               : h * std::min(vij_xij, 0.0) / (r2 + eta2h2);
    const double Pi = (-alpha_c * mu + beta * mu * mu) / (0.5 * (rhoi + rho[j]));
    const double mgs = m[j] * gw * (s - Pi);
    a0 += mgs * x0;
    a1 += mgs * x1;
    a2 += mgs * x2;
  }
  g.acc[3 * i] = a0;
  g.acc[3 * i + 1] = a1;
  g.acc[3 * i + 2] = a2;
}

/// True when R (eq. 9) is 0 for particle i and all its neighbours, read from the bit set of
/// mark_tension(). One bit per particle instead of R's trace (three doubles on a cache line of
/// their own): the test reads 64 particles per word, and it vectorises (no early exit).
SPHFORGE_ALWAYS_INLINE bool no_tension_around(const std::uint64_t* tension, std::size_t i, const std::uint32_t* nb,
                                              std::ptrdiff_t count) {
  std::uint64_t any = (tension[i >> 6] >> (i & 63)) & 1u;
#pragma omp simd reduction(| : any)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const std::uint32_t j = nb[k];
    any |= (tension[j >> 6] >> (j & 63)) & 1u;
  }
  return any == 0;
}

template <KernelKind K, int Exponent, bool Failure, bool Variable>
SPHFORGE_ALWAYS_INLINE void momentum_particle(const MomentumArgs& g, const PairKernel<K>& kernel, std::size_t i) {
  const DecodedList list(*g.nl, i);
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(list.count);
  // Where neither i nor any neighbour is under principal tension, every artificial-stress term is
  // an exact 0 (eq. 9): the loop without it gives the same sums to the bit (same kernel factor,
  // same order) and skips the six gathers of R_j per pair. The usual case in forming, where most
  // of the material is in compression: a scene pays for the artificial stress only where it acts.
  if constexpr (Exponent != 0) {
    if (g.tension && no_tension_around(g.tension, i, list.indices, count)) {
      momentum_sums<K, 0, Failure, Variable>(g, kernel, i, list.indices, count);
      return;
    }
  }
  momentum_sums<K, Exponent, Failure, Variable>(g, kernel, i, list.indices, count);
}

template <KernelKind K, int Exponent, bool Failure, bool Variable>
void momentum_rate_run(const MomentumArgs& g) {
  const PairKernel<K> kernel(g.h);
  for_each_particle(g.n, [&](std::size_t i) SPHFORGE_PAIR_LAMBDA {
    if (Failure && g.failure.failed[i] != 0.0) momentum_particle<K, Exponent, Failure, Variable>(g, kernel, i);
    else momentum_particle<K, Exponent, false, Variable>(g, kernel, i);  // an intact particle has no broken bond (eq. 111)
  });
}

template <KernelKind K, int Exponent>
void momentum_rate_impl(const MomentumArgs& g) {
  if (g.h_point) {
    if (g.failure.failed) momentum_rate_run<K, Exponent, true, true>(g);
    else momentum_rate_run<K, Exponent, false, true>(g);
  } else {
    if (g.failure.failed) momentum_rate_run<K, Exponent, true, false>(g);
    else momentum_rate_run<K, Exponent, false, false>(g);
  }
}
}  // namespace

PairLoopIsa limit_pair_loop_isa(PairLoopIsa limit) {
  return static_cast<PairLoopIsa>(g_isa_limit.exchange(static_cast<int>(limit)));
}

PairLoopIsa pair_loop_isa() {
#if defined(__GNUC__) && defined(__x86_64__)
  static const PairLoopIsa cpu_best = [] {
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return PairLoopIsa::generic;
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq"))
      return PairLoopIsa::avx512vl;
    return PairLoopIsa::avx2;
  }();
  return static_cast<PairLoopIsa>(
      std::min(static_cast<int>(cpu_best), g_isa_limit.load(std::memory_order_relaxed)));
#else
  return PairLoopIsa::generic;
#endif
}

void velocity_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* v,
                       const double* volume, bool corrected, double* L, double* condition, double* correction,
                       std::size_t n, const BondFailure& failure, const double* h_point) {
  if (kernel == KernelKind::WendlandC2) {
    if (corrected)
      velocity_gradient_impl<KernelKind::WendlandC2, true>(nl, h, x, v, volume, L, n, condition, correction, failure,
                                                           h_point);
    else
      velocity_gradient_impl<KernelKind::WendlandC2, false>(nl, h, x, v, volume, L, n, condition, nullptr, failure,
                                                            h_point);
  } else {
    if (corrected)
      velocity_gradient_impl<KernelKind::CubicSpline, true>(nl, h, x, v, volume, L, n, condition, correction, failure,
                                                            h_point);
    else
      velocity_gradient_impl<KernelKind::CubicSpline, false>(nl, h, x, v, volume, L, n, condition, nullptr, failure,
                                                             h_point);
  }
}

void corrected_stress(const double* pressure, const double* S, const double* correction, bool correct_pressure,
                      double* stress_c, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double* s = S + 6 * i;
    // The part C multiplies: sigma = S - p I (eq. 7), or S alone (eq. 7b: -p I is added uncorrected below).
    const double p_c = correct_pressure ? pressure[i] : 0.0;
    const double sigma[9] = {s[0] - p_c, s[3], s[5], s[3], s[1] - p_c, s[4], s[5], s[4], s[2] - p_c};
    double* out = stress_c + 9 * i;
    if (correction) {
      const double* k = correction + 6 * i;
      const double C[9] = {k[0], k[3], k[5], k[3], k[1], k[4], k[5], k[4], k[2]};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          out[3 * a + b] = sigma[3 * a] * C[b] + sigma[3 * a + 1] * C[3 + b] + sigma[3 * a + 2] * C[6 + b];
    } else {  // eq. 7a: A = sigma
      for (int c = 0; c < 9; ++c) out[c] = sigma[c];
    }
    for (int c = 0; c < 9; c += 4) out[c] -= pressure[i] - p_c;  // the uncorrected pressure (eqs. 7a, 7b)
  }
}

void particle_volume(const double* mass, const double* density, double* volume, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) volume[i] = mass[i] / density[i];
}

void stress_over_density_squared(const double* pressure, const double* S, const double* density,
                                 double* sigma_over_rho2, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double inv = 1.0 / (density[i] * density[i]);
    for (int c = 0; c < 6; ++c) sigma_over_rho2[6 * i + c] = S[6 * i + c] * inv;
    for (int c = 0; c < 3; ++c) sigma_over_rho2[6 * i + c] -= pressure[i] * inv;
  }
}

void continuity_density_rate(const double* L, const double* density, double* density_rate, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    density_rate[i] = -density[i] * (L[9 * i] + L[9 * i + 4] + L[9 * i + 8]);
}

void jaumann_rotation(const double* L, double dt, double* S, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double* l = L + 9 * i;
    // Spin Omega = (L - L^T)/2 and the Hughes-Winget (Cayley) rotation over the step,
    // Q = (I - W)^-1 (I + W), W = dt/2 Omega   (eq. 6): exactly orthogonal, so a rigidly rotating
    // stress keeps its invariants to round-off, and S + dt (Omega S - S Omega) to second order.
    // W is skew with axial vector w (W u = w x u), so W^2 = w w^T - |w|^2 I and the inverse has a
    // closed form: Q = I + 2 (W + W^2) / (1 + |w|^2) (eq. 6a), without a 3x3 inversion.
    const double w0 = 0.25 * dt * (l[7] - l[5]), w1 = 0.25 * dt * (l[2] - l[6]), w2 = 0.25 * dt * (l[3] - l[1]);
    const double theta2 = w0 * w0 + w1 * w1 + w2 * w2, c = 2.0 / (1.0 + theta2);
    const double q[3][3] = {{1.0 + c * (w0 * w0 - theta2), c * (w0 * w1 - w2), c * (w0 * w2 + w1)},
                            {c * (w1 * w0 + w2), 1.0 + c * (w1 * w1 - theta2), c * (w1 * w2 - w0)},
                            {c * (w2 * w0 - w1), c * (w2 * w1 + w0), 1.0 + c * (w2 * w2 - theta2)}};
    double* s = S + 6 * i;
    const double sm[3][3] = {{s[0], s[3], s[5]}, {s[3], s[1], s[4]}, {s[5], s[4], s[2]}};
    double qs[3][3];  // Q S
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) qs[a][b] = q[a][0] * sm[0][b] + q[a][1] * sm[1][b] + q[a][2] * sm[2][b];
    // Q S Q^T is symmetric: its six entries xx yy zz xy yz xz
    constexpr int kRow[6] = {0, 1, 2, 0, 1, 0}, kCol[6] = {0, 1, 2, 1, 2, 2};
    for (int e = 0; e < 6; ++e) {
      const int a = kRow[e], b = kCol[e];
      s[e] = qs[a][0] * q[b][0] + qs[a][1] * q[b][1] + qs[a][2] * q[b][2];
    }
  }
}

namespace {
template <KernelKind K>
void momentum_rate_kernel(const MomentumArgs& g, bool stress) {
  if (!stress) momentum_rate_impl<K, 0>(g);
  else if (g.exponent == 4.0) momentum_rate_impl<K, 4>(g);
  else momentum_rate_impl<K, -1>(g);
}
}  // namespace

void momentum_rate(const NeighbourList& nl, KernelKind kernel, double h, const ArtificialViscosity& av,
                   double sound_speed, const double* x, const double* v, const double* mass, const double* density,
                   const double* volume, const double* stress_c, const ArtificialStress& as, const double* R,
                   const std::uint64_t* tension, double* acceleration, std::size_t n, const BondFailure& failure,
                   const double* h_point) {
  const bool stress = R != nullptr && as.epsilon > 0.0;
  const MomentumArgs g{&nl, x, v, mass, density, volume, stress_c, R, tension, acceleration, n, h,
                       av.eta * av.eta * h * h, av.alpha * sound_speed, av.beta,
                       stress ? 1.0 / as.w_dx : 0.0, as.exponent, failure, h_point, av.eta * av.eta,
                       stress && h_point ? 1.0 / as.w_dx_unit : 0.0};
  if (kernel == KernelKind::WendlandC2) momentum_rate_kernel<KernelKind::WendlandC2>(g, stress);
  else momentum_rate_kernel<KernelKind::CubicSpline>(g, stress);
}

void artificial_stress(const double* sigma_over_rho2, double epsilon, double* R, std::size_t n) {
  // Dynamic chunks: the particles under tension, which cost an eigen-decomposition, cluster in space.
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < n; ++i) {
    const double* t = sigma_over_rho2 + 6 * i;
    double* out = R + 6 * i;
    // Gershgorin: every eigenvalue lies below max_a (t_aa + sum_b!=a |t_ab|). Where that bound is
    // <= 0 (the particle is under no principal tension, the common case in forming), R is 0
    // (eq. 9) and the eigen-decomposition is skipped: the same zeros it would give.
    const double bound = std::max({t[0] + std::abs(t[3]) + std::abs(t[5]), t[1] + std::abs(t[3]) + std::abs(t[4]),
                                   t[2] + std::abs(t[4]) + std::abs(t[5])});
    if (bound <= 0.0) {
      for (int c = 0; c < 6; ++c) out[c] = 0.0;
      continue;
    }
    Eigen::Matrix3d sigma;
    sigma << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(sigma);
    const Eigen::Vector3d principal = eig.eigenvalues();
    Eigen::Vector3d r_principal;
    for (int k = 0; k < 3; ++k) r_principal[k] = principal[k] > 0.0 ? -epsilon * principal[k] : 0.0;
    const Eigen::Matrix3d r = eig.eigenvectors() * r_principal.asDiagonal() * eig.eigenvectors().transpose();
    out[0] = r(0, 0);
    out[1] = r(1, 1);
    out[2] = r(2, 2);
    out[3] = r(0, 1);
    out[4] = r(1, 2);
    out[5] = r(0, 2);
  }
}

void mark_tension(const double* R, std::size_t count, std::uint64_t* tension) {
  const std::size_t words = (count + 63) / 64;
  // Each word is written by one thread: no atomics, and the set does not depend on the thread count.
#pragma omp parallel for schedule(static)
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t bits = 0;
    const std::size_t first = 64 * w, end = std::min(count, first + 64);
    for (std::size_t i = first; i < end; ++i)
      bits |= static_cast<std::uint64_t>(R[6 * i] + R[6 * i + 1] + R[6 * i + 2] != 0.0) << (i - first);
    tension[w] = bits;
  }
}

void cauchy_stress(const double* pressure, const double* S, double* sigma, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 6; ++c) sigma[6 * i + c] = S[6 * i + c];
    for (int c = 0; c < 3; ++c) sigma[6 * i + c] -= pressure[i];
  }
}

}  // namespace sphforge
