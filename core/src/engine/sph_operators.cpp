#include "engine/sph_operators.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace sphforge {

namespace {
inline double power(double base, int n) {
  double r = base;
  for (int k = 1; k < n; ++k) r *= base;
  return r;
}

// Symmetric 6-component storage (xx yy zz xy yz xz) <-> 3x3 index.
constexpr int kSym[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};

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
  double factor(double r2) const {
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
  void factor_and_value(double r2, double& F, double& W) const {
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

template <KernelKind K, bool Corrected>
void velocity_gradient_impl(const NeighbourList& nl, double h, const double* x, const double* v,
                            const double* volume, double* L, std::size_t n, double* condition) {
  const PairKernel<K> kernel(h);
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) {
    double l[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    // M_i = -sum_j V_j x_ij (x) grad_i W_ij (eq. 3a), symmetric: xx yy zz xy yz xz
    double mom6[6] = {0, 0, 0, 0, 0, 0};
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    const double vi[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    const std::uint32_t* const last = nl.end(i);
    for (const std::uint32_t* p = nl.begin(i); p != last; ++p) {
      const std::size_t j = *p;
      const double xij[3] = {xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]};
      const double r2 = xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2];
      const double f = kernel.factor(r2) * volume[j];  // V_j (dW/dr)/r; 0 beyond the support
      const double dv[3] = {(v[3 * j] - vi[0]) * f, (v[3 * j + 1] - vi[1]) * f, (v[3 * j + 2] - vi[2]) * f};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) l[3 * a + b] += dv[a] * xij[b];
      if constexpr (Corrected) {
        const double fx[3] = {f * xij[0], f * xij[1], f * xij[2]};
        mom6[0] -= fx[0] * xij[0];
        mom6[1] -= fx[1] * xij[1];
        mom6[2] -= fx[2] * xij[2];
        mom6[3] -= fx[0] * xij[1];
        mom6[4] -= fx[1] * xij[2];
        mom6[5] -= fx[0] * xij[2];
      }
    }
    if constexpr (Corrected) {
      // Corrected gradient L = G M^-1 (eq. 3b), exact for linear fields also where the
      // neighbourhood is truncated (walls, free surfaces). M is dimensionless (I on a full,
      // regular neighbourhood), so its conditioning can be judged without units: where
      // det M < 0.05 or the inverse is large, too few neighbours span some direction and the
      // uncorrected gradient (M = I) is used instead.
      double mom[9];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) mom[3 * a + b] = mom6[kSym[a][b]];
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> G(l), M(mom);
      const double det = M.determinant();
      double cond = 0.0;
      if (det > 0.05) {
        const Eigen::Matrix3d Minv = M.inverse();
        cond = M.norm() * Minv.norm();
        if (cond < 50.0) {
          const Eigen::Matrix3d corrected = G * Minv;
          Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(L + 9 * i) = corrected;
          if (condition) condition[i] = cond;
          continue;
        }
      }
      if (condition) condition[i] = -1.0;  // fallback used
    }
    for (int c = 0; c < 9; ++c) L[9 * i + c] = l[c];
  }
}

template <KernelKind K, bool WithArtificialStress, bool IntegerExponent>
void momentum_rate_impl(const NeighbourList& nl, double h, const ArtificialViscosity& av, double c0,
                        const double* x, const double* v, const double* m, const double* rho,
                        const double* sigma_over_rho2, const ArtificialStress& as, const double* R, double* acc,
                        std::size_t n) {
  const PairKernel<K> kernel(h);
  const double eta2h2 = av.eta * av.eta * h * h;
  const double alpha_c = av.alpha * c0, beta = av.beta;
  const double inv_w_dx = WithArtificialStress ? 1.0 / as.w_dx : 0.0;
  // The usual exponents (n = 4) are integers: multiply instead of calling pow() per pair.
  const int integer_exponent = IntegerExponent ? int(as.exponent) : 0;
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) {
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    const double vi[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    const double rhoi = rho[i];
    double ti[6], Ri[6];
    for (int c = 0; c < 6; ++c) {
      ti[c] = sigma_over_rho2[6 * i + c];
      Ri[c] = WithArtificialStress ? R[6 * i + c] : 0.0;
    }
    double a[3] = {0, 0, 0};
    const std::uint32_t* const last = nl.end(i);
    for (const std::uint32_t* q = nl.begin(i); q != last; ++q) {
      const std::size_t j = *q;
      const double xij[3] = {xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]};
      const double r2 = xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2];
      // grad_i W_ij = gw * x_ij. Pairs in the Verlet skin (gw = 0) run through too and add an
      // exact 0: cheaper than an unpredictable branch.
      double gw, w;
      if constexpr (WithArtificialStress) kernel.factor_and_value(r2, gw, w);
      else gw = kernel.factor(r2);
      // sigma_i/rho_i^2 + sigma_j/rho_j^2, sigma = S - p I  (eq. 7)
      const double* tj = sigma_over_rho2 + 6 * j;
      double t[6];
      for (int c = 0; c < 6; ++c) t[c] = ti[c] + tj[c];
      if constexpr (WithArtificialStress) {
        // f_ij^n (R_i + R_j), f_ij = W(r_ij)/W(dx)  (eq. 9); R is zero for particles under no
        // principal tension, and then this adds an exact 0.
        const double fw = w * inv_w_dx;
        const double f = IntegerExponent ? power(fw, integer_exponent) : std::pow(fw, as.exponent);
        for (int c = 0; c < 6; ++c) t[c] += f * (Ri[c] + R[6 * j + c]);
      }
      // Monaghan artificial viscosity, only for approaching pairs  (eq. 8)
      const double vij_xij = (vi[0] - v[3 * j]) * xij[0] + (vi[1] - v[3 * j + 1]) * xij[1] +
                             (vi[2] - v[3 * j + 2]) * xij[2];
      const double mu = h * std::min(vij_xij, 0.0) / (r2 + eta2h2);
      const double Pi = (-alpha_c * mu + beta * mu * mu) / (0.5 * (rhoi + rho[j]));
      t[0] -= Pi;
      t[1] -= Pi;
      t[2] -= Pi;
      const double mg = m[j] * gw;
      for (int aa = 0; aa < 3; ++aa)
        a[aa] += mg * (t[kSym[aa][0]] * xij[0] + t[kSym[aa][1]] * xij[1] + t[kSym[aa][2]] * xij[2]);
    }
    acc[3 * i] = a[0];
    acc[3 * i + 1] = a[1];
    acc[3 * i + 2] = a[2];
  }
}
}  // namespace

void velocity_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* v,
                       const double* volume, bool corrected, double* L, double* condition, std::size_t n) {
  if (kernel == KernelKind::WendlandC2) {
    if (corrected) velocity_gradient_impl<KernelKind::WendlandC2, true>(nl, h, x, v, volume, L, n, condition);
    else velocity_gradient_impl<KernelKind::WendlandC2, false>(nl, h, x, v, volume, L, n, condition);
  } else {
    if (corrected) velocity_gradient_impl<KernelKind::CubicSpline, true>(nl, h, x, v, volume, L, n, condition);
    else velocity_gradient_impl<KernelKind::CubicSpline, false>(nl, h, x, v, volume, L, n, condition);
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
    double w[3][3], s[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        w[a][b] = 0.5 * (l[3 * a + b] - l[3 * b + a]);
        s[a][b] = S[6 * i + kSym[a][b]];
      }
    // Omega S - S Omega is symmetric when S is symmetric and Omega antisymmetric.
    double r[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        double acc = 0.0;
        for (int k = 0; k < 3; ++k) acc += w[a][k] * s[k][b] - s[a][k] * w[k][b];
        r[a][b] = acc;
      }
    S[6 * i + 0] += dt * r[0][0];
    S[6 * i + 1] += dt * r[1][1];
    S[6 * i + 2] += dt * r[2][2];
    S[6 * i + 3] += dt * r[0][1];
    S[6 * i + 4] += dt * r[1][2];
    S[6 * i + 5] += dt * r[0][2];
  }
}

namespace {
template <KernelKind K>
void momentum_rate_kernel(const NeighbourList& nl, double h, const ArtificialViscosity& av, double c0,
                          const double* x, const double* v, const double* m, const double* rho,
                          const double* sigma_over_rho2, const ArtificialStress& as, const double* R, double* acc,
                          std::size_t n) {
  const bool stress = R != nullptr && as.epsilon > 0.0;
  const bool integer_exponent = as.exponent == std::floor(as.exponent) && as.exponent >= 1.0 && as.exponent <= 12.0;
  if (!stress)
    momentum_rate_impl<K, false, true>(nl, h, av, c0, x, v, m, rho, sigma_over_rho2, as, R, acc, n);
  else if (integer_exponent)
    momentum_rate_impl<K, true, true>(nl, h, av, c0, x, v, m, rho, sigma_over_rho2, as, R, acc, n);
  else
    momentum_rate_impl<K, true, false>(nl, h, av, c0, x, v, m, rho, sigma_over_rho2, as, R, acc, n);
}
}  // namespace

void momentum_rate(const NeighbourList& nl, KernelKind kernel, double h, const ArtificialViscosity& av,
                   double sound_speed, const double* x, const double* v, const double* mass, const double* density,
                   const double* sigma_over_rho2, const ArtificialStress& as, const double* R,
                   double* acceleration, std::size_t n) {
  if (kernel == KernelKind::WendlandC2)
    momentum_rate_kernel<KernelKind::WendlandC2>(nl, h, av, sound_speed, x, v, mass, density, sigma_over_rho2, as,
                                                 R, acceleration, n);
  else
    momentum_rate_kernel<KernelKind::CubicSpline>(nl, h, av, sound_speed, x, v, mass, density, sigma_over_rho2, as,
                                                  R, acceleration, n);
}

void artificial_stress(const double* sigma_over_rho2, double epsilon, double* R, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double* t = sigma_over_rho2 + 6 * i;
    Eigen::Matrix3d sigma;
    sigma << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(sigma);
    const Eigen::Vector3d principal = eig.eigenvalues();
    Eigen::Vector3d r_principal;
    for (int k = 0; k < 3; ++k) r_principal[k] = principal[k] > 0.0 ? -epsilon * principal[k] : 0.0;
    const Eigen::Matrix3d r = eig.eigenvectors() * r_principal.asDiagonal() * eig.eigenvectors().transpose();
    double* out = R + 6 * i;
    out[0] = r(0, 0);
    out[1] = r(1, 1);
    out[2] = r(2, 2);
    out[3] = r(0, 1);
    out[4] = r(1, 2);
    out[5] = r(0, 2);
  }
}

}  // namespace sphforge
