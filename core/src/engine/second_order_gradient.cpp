#include "engine/second_order_gradient.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "engine/pair_kernel.hpp"

namespace sphforge {

namespace {

// Scaled Taylor basis of a pair (eq. 130): p = (d/h, q(d)/h^2), q = (dx^2, dy^2, dz^2, dx dy, dy dz, dx dz),
// d = x_j - x_i. Scaling by h makes the moment matrix dimensionless, so that its condition number can
// be judged without units (as for the first-order M, eq. 3b).
SPHFORGE_PAIR_INLINE void taylor_basis(double d0, double d1, double d2, double inv_h, double p[9]) {
  const double e0 = d0 * inv_h, e1 = d1 * inv_h, e2 = d2 * inv_h;
  p[0] = e0, p[1] = e1, p[2] = e2;
  p[3] = e0 * e0, p[4] = e1 * e1, p[5] = e2 * e2;
  p[6] = e0 * e1, p[7] = e1 * e2, p[8] = e0 * e2;
}

template <KernelKind K>
void correction_impl(const NeighbourList& nl, double h, const double* x, const double* volume, double* B, double* C,
                     double* condition, std::size_t n) {
  const PairKernel<K> kernel(h);
  const double inv_h = 1.0 / h;
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) {
    // Quadratic moment matrix M2_i = sum_j V_j W_ij p p^T (eq. 131), upper triangle row by row
    // (45 entries), and the first-order M_i = -sum_j V_j x_ij (x) grad_i W_ij (eq. 3a) for the fallback.
    double m2[45] = {};
    double m1[6] = {};
    const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
    const DecodedList list(nl, i);
    const std::uint32_t* const nb = list.indices;
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(list.count);
    for (std::ptrdiff_t k = 0; k < count; ++k) {
      const std::size_t j = nb[k];
      const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
      double F, W;
      kernel.factor_and_value(d0 * d0 + d1 * d1 + d2 * d2, F, W);
      const double w = volume[j] * W, f = volume[j] * F;
      double p[9];
      taylor_basis(d0, d1, d2, inv_h, p);
      int e = 0;
      for (int a = 0; a < 9; ++a) {
        const double wp = w * p[a];
        for (int b = a; b < 9; ++b) m2[e++] += wp * p[b];
      }
      // x_ij = -d, so -V F x_ij (x) x_ij = -f d (x) d
      m1[0] -= f * d0 * d0, m1[1] -= f * d1 * d1, m1[2] -= f * d2 * d2;
      m1[3] -= f * d0 * d1, m1[4] -= f * d1 * d2, m1[5] -= f * d0 * d2;
    }
    Eigen::Matrix<double, 9, 9> M;
    int e = 0;
    for (int a = 0; a < 9; ++a)
      for (int b = a; b < 9; ++b) M(a, b) = M(b, a) = m2[e++];
    double* b_i = B + 27 * i;
    double* c_i = C + 6 * i;
    // M2 is a sum of w p p^T with w >= 0: symmetric positive semi-definite, so Cholesky either succeeds
    // or reports that some quadratic direction is not spanned by the neighbours.
    const Eigen::LLT<Eigen::Matrix<double, 9, 9>> llt(M);
    const double cond = llt.info() == Eigen::Success ? 1.0 / llt.rcond() : -1.0;
    if (cond > 0.0 && cond < kSecondOrderMaxCondition) {
      // Only the gradient rows of M2^-1 are needed (eq. 132): solve for its first three columns
      // (M2 symmetric), then fold the 1/h of the basis in.
      const Eigen::Matrix<double, 9, 3> X = llt.solve(Eigen::Matrix<double, 9, 3>::Identity());
      for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 9; ++k) b_i[9 * a + k] = X(k, a) * inv_h;
      for (int c = 0; c < 6; ++c) c_i[c] = 0.0;
      if (condition) condition[i] = cond;
      continue;
    }
    // Fallback (eq. 134): the first-order correction with the criteria of eq. 3b, else the plain gradient.
    for (int c = 0; c < 27; ++c) b_i[c] = 0.0;
    if (condition) condition[i] = -1.0;
    Eigen::Matrix3d M1;
    M1 << m1[0], m1[3], m1[5], m1[3], m1[1], m1[4], m1[5], m1[4], m1[2];
    const double det = M1.determinant();
    if (det > 1e-3) {
      const Eigen::Matrix3d inv = M1.inverse();
      if (M1.norm() * inv.norm() < 1000.0) {
        c_i[0] = inv(0, 0), c_i[1] = inv(1, 1), c_i[2] = inv(2, 2);
        c_i[3] = 0.5 * (inv(0, 1) + inv(1, 0)), c_i[4] = 0.5 * (inv(1, 2) + inv(2, 1));
        c_i[5] = 0.5 * (inv(0, 2) + inv(2, 0));
        continue;
      }
    }
    c_i[0] = c_i[1] = c_i[2] = 1.0;
    c_i[3] = c_i[4] = c_i[5] = 0.0;
  }
}

template <KernelKind K>
void gradient_impl(const NeighbourList& nl, double h, const double* x, const double* v, const double* volume,
                   const double* B, const double* C, double* L, std::size_t n) {
  const PairKernel<K> kernel(h);
  const double inv_h = 1.0 / h;
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) {
    double b[27];
    for (int c = 0; c < 27; ++c) b[c] = B[27 * i + c];
    const double* ci = C + 6 * i;
    const double c00 = ci[0], c11 = ci[1], c22 = ci[2], c01 = ci[3], c12 = ci[4], c02 = ci[5];
    const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
    const double vi0 = v[3 * i], vi1 = v[3 * i + 1], vi2 = v[3 * i + 2];
    double l0 = 0, l1 = 0, l2 = 0, l3 = 0, l4 = 0, l5 = 0, l6 = 0, l7 = 0, l8 = 0;
    const DecodedList list(nl, i);
    const std::uint32_t* const nb = list.indices;
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(list.count);
#pragma omp simd reduction(+ : l0, l1, l2, l3, l4, l5, l6, l7, l8)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
      const std::size_t j = nb[k];
      const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
      double F, W;
      kernel.factor_and_value(d0 * d0 + d1 * d1 + d2 * d2, F, W);
      const double w = volume[j] * W, f = volume[j] * F;
      double p[9];
      taylor_basis(d0, d1, d2, inv_h, p);
      // Pair weight g_ij = V_j [W B_i p - F C_i d]   (eq. 133)
      double g[3];
      for (int a = 0; a < 3; ++a) {
        double s = 0.0;
        for (int c = 0; c < 9; ++c) s += b[9 * a + c] * p[c];
        g[a] = w * s;
      }
      g[0] -= f * (c00 * d0 + c01 * d1 + c02 * d2);
      g[1] -= f * (c01 * d0 + c11 * d1 + c12 * d2);
      g[2] -= f * (c02 * d0 + c12 * d1 + c22 * d2);
      const double u0 = v[3 * j] - vi0, u1 = v[3 * j + 1] - vi1, u2 = v[3 * j + 2] - vi2;
      l0 += u0 * g[0], l1 += u0 * g[1], l2 += u0 * g[2];
      l3 += u1 * g[0], l4 += u1 * g[1], l5 += u1 * g[2];
      l6 += u2 * g[0], l7 += u2 * g[1], l8 += u2 * g[2];
    }
    double* out = L + 9 * i;
    out[0] = l0, out[1] = l1, out[2] = l2, out[3] = l3, out[4] = l4, out[5] = l5, out[6] = l6, out[7] = l7,
    out[8] = l8;
  }
}

template <KernelKind K>
void momentum_impl(const NeighbourList& nl, double h, const double* x, const double* mass, const double* volume,
                   const double* stress_b, double* acc, std::size_t n) {
  const PairKernel<K> kernel(h);
  const double inv_h = 1.0 / h;
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) {
    double ai[27];
    for (int c = 0; c < 27; ++c) ai[c] = stress_b[27 * i + c];
    const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
    double s0 = 0, s1 = 0, s2 = 0;
    const DecodedList list(nl, i);
    const std::uint32_t* const nb = list.indices;
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(list.count);
#pragma omp simd reduction(+ : s0, s1, s2)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
      const std::size_t j = nb[k];
      const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
      double F, W;
      kernel.factor_and_value(d0 * d0 + d1 * d1 + d2 * d2, F, W);
      const double w = volume[j] * W;
      double p[9];
      taylor_basis(d0, d1, d2, inv_h, p);
      // A_i p(d) - A_j p(-d), p(-d) = (-d/h, q/h^2): linear columns add, quadratic ones subtract (eq. 136).
      const double* aj = stress_b + 27 * j;
      double s[3];
      for (int a = 0; a < 3; ++a) {
        double t = 0.0;
        for (int c = 0; c < 3; ++c) t += (ai[9 * a + c] + aj[9 * a + c]) * p[c];
        for (int c = 3; c < 9; ++c) t += (ai[9 * a + c] - aj[9 * a + c]) * p[c];
        s[a] = w * t;
      }
      s0 += s[0], s1 += s[1], s2 += s[2];
    }
    const double inv_rhoi = volume[i] / mass[i];  // V_i / m_i, as in eq. 7
    acc[3 * i] += inv_rhoi * s0;
    acc[3 * i + 1] += inv_rhoi * s1;
    acc[3 * i + 2] += inv_rhoi * s2;
  }
}

}  // namespace

void second_order_correction(const NeighbourList& nl, KernelKind kernel, double h, const double* x,
                             const double* volume, double* B, double* C, double* condition, std::size_t n) {
  if (kernel == KernelKind::WendlandC2)
    correction_impl<KernelKind::WendlandC2>(nl, h, x, volume, B, C, condition, n);
  else
    correction_impl<KernelKind::CubicSpline>(nl, h, x, volume, B, C, condition, n);
}

void second_order_velocity_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x,
                                    const double* v, const double* volume, const double* B, const double* C,
                                    double* L, std::size_t n) {
  if (kernel == KernelKind::WendlandC2) gradient_impl<KernelKind::WendlandC2>(nl, h, x, v, volume, B, C, L, n);
  else gradient_impl<KernelKind::CubicSpline>(nl, h, x, v, volume, B, C, L, n);
}

void second_order_stress(const double* pressure, const double* S, const double* B, double* stress_b, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double* s = S + 6 * i;
    const double sigma[9] = {s[0] - pressure[i], s[3], s[5], s[3], s[1] - pressure[i], s[4],
                             s[5], s[4], s[2] - pressure[i]};
    const double* b = B + 27 * i;
    double* out = stress_b + 27 * i;
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 9; ++k)
        out[9 * a + k] = sigma[3 * a] * b[k] + sigma[3 * a + 1] * b[9 + k] + sigma[3 * a + 2] * b[18 + k];
  }
}

void second_order_momentum_term(const NeighbourList& nl, KernelKind kernel, double h, const double* x,
                                const double* mass, const double* volume, const double* stress_b,
                                double* acceleration, std::size_t n) {
  if (kernel == KernelKind::WendlandC2)
    momentum_impl<KernelKind::WendlandC2>(nl, h, x, mass, volume, stress_b, acceleration, n);
  else
    momentum_impl<KernelKind::CubicSpline>(nl, h, x, mass, volume, stress_b, acceleration, n);
}

}  // namespace sphforge
