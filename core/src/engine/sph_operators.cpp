#include "engine/sph_operators.hpp"

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

template <KernelKind K, bool Corrected>
void velocity_gradient_impl(const NeighbourList& nl, double h, const double* x, const double* v,
                            const double* volume, double* L, std::size_t n, double* condition) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double l[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    double mom[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // M_i = -sum_j V_j x_ij (x) grad_i W_ij (eq. 3a)
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    const double vi[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    for (const std::uint32_t* p = nl.begin(i); p != nl.end(i); ++p) {
      const std::size_t j = *p;
      const double xij[3] = {xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]};
      const double r = std::sqrt(xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2]);
      const double f = kernel_gradient_factor(K, r, h) * volume[j];  // V_j (dW/dr)/r
      const double dv[3] = {(v[3 * j] - vi[0]) * f, (v[3 * j + 1] - vi[1]) * f, (v[3 * j + 2] - vi[2]) * f};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) l[3 * a + b] += dv[a] * xij[b];
      if constexpr (Corrected) {
        const double fx[3] = {-f * xij[0], -f * xij[1], -f * xij[2]};
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) mom[3 * a + b] += fx[a] * xij[b];
      }
    }
    if constexpr (Corrected) {
      // Corrected gradient L = G M^-1 (eq. 3b), exact for linear fields also where the
      // neighbourhood is truncated (walls, free surfaces). M is dimensionless (I on a full,
      // regular neighbourhood), so its conditioning can be judged without units: where
      // det M < 0.05 or the inverse is large, too few neighbours span some direction and the
      // uncorrected gradient (M = I) is used instead.
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

template <KernelKind K, bool WithArtificialStress>
void momentum_rate_impl(const NeighbourList& nl, double h, const ArtificialViscosity& av, double c0,
                        const double* x, const double* v, const double* m, const double* rho,
                        const double* sigma_over_rho2, const ArtificialStress& as, const double* R, double* acc,
                        std::size_t n) {
  const double eta2h2 = av.eta * av.eta * h * h;
  const double inv_w_dx = WithArtificialStress ? 1.0 / as.w_dx : 0.0;
  // The usual exponents (n = 4) are integers: multiply instead of calling pow() per pair.
  const int integer_exponent =
      (as.exponent == std::floor(as.exponent) && as.exponent >= 1.0 && as.exponent <= 12.0) ? int(as.exponent) : 0;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    const double vi[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    const double* ti = sigma_over_rho2 + 6 * i;
    double a[3] = {0, 0, 0};
    for (const std::uint32_t* q = nl.begin(i); q != nl.end(i); ++q) {
      const std::size_t j = *q;
      const double xij[3] = {xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]};
      const double r2 = xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2];
      const double gw = kernel_gradient_factor(K, std::sqrt(r2), h);  // grad_i W_ij = gw * x_ij
      if (gw == 0.0) continue;  // outside the support (the list includes the Verlet skin)
      // sigma_i/rho_i^2 + sigma_j/rho_j^2, sigma = S - p I  (eq. 7)
      const double* tj = sigma_over_rho2 + 6 * j;
      double t[6];
      for (int c = 0; c < 6; ++c) t[c] = ti[c] + tj[c];
      if constexpr (WithArtificialStress) {
        // f_ij^n (R_i + R_j), f_ij = W(r_ij)/W(dx)  (eq. 9); R is zero for particles under no
        // principal tension, so most pairs of a compressed body skip the kernel evaluation.
        double rsum[6];
        bool any = false;
        for (int c = 0; c < 6; ++c) {
          rsum[c] = R[6 * i + c] + R[6 * j + c];
          any = any || rsum[c] != 0.0;
        }
        if (any) {
          const double f = integer_exponent > 0
                               ? power(kernel_value(K, std::sqrt(r2), h) * inv_w_dx, integer_exponent)
                               : std::pow(kernel_value(K, std::sqrt(r2), h) * inv_w_dx, as.exponent);
          for (int c = 0; c < 6; ++c) t[c] += f * rsum[c];
        }
      }
      // Monaghan artificial viscosity, only for approaching pairs  (eq. 8)
      const double vij_xij = (vi[0] - v[3 * j]) * xij[0] + (vi[1] - v[3 * j + 1]) * xij[1] +
                             (vi[2] - v[3 * j + 2]) * xij[2];
      if (vij_xij < 0.0) {
        const double mu = h * vij_xij / (r2 + eta2h2);
        const double Pi = (-av.alpha * c0 * mu + av.beta * mu * mu) / (0.5 * (rho[i] + rho[j]));
        t[0] -= Pi;
        t[1] -= Pi;
        t[2] -= Pi;
      }
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
    // Spin Omega = (L - L^T)/2 and the Hughes-Winget (Cayley) rotation over the step,
    // Q = (I - dt/2 Omega)^-1 (I + dt/2 Omega)   (eq. 6): exactly orthogonal, so a rigidly
    // rotating stress keeps its invariants to round-off, and S + dt (Omega S - S Omega) to
    // second order.
    Eigen::Matrix3d half_w;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) half_w(a, b) = 0.25 * dt * (l[3 * a + b] - l[3 * b + a]);
    const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d q = (identity - half_w).inverse() * (identity + half_w);
    Eigen::Matrix3d s;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) s(a, b) = S[6 * i + kSym[a][b]];
    const Eigen::Matrix3d rotated = q * s * q.transpose();
    S[6 * i + 0] = rotated(0, 0);
    S[6 * i + 1] = rotated(1, 1);
    S[6 * i + 2] = rotated(2, 2);
    // Off-diagonal terms averaged: the product is symmetric up to round-off.
    S[6 * i + 3] = 0.5 * (rotated(0, 1) + rotated(1, 0));
    S[6 * i + 4] = 0.5 * (rotated(1, 2) + rotated(2, 1));
    S[6 * i + 5] = 0.5 * (rotated(0, 2) + rotated(2, 0));
  }
}

void momentum_rate(const NeighbourList& nl, KernelKind kernel, double h, const ArtificialViscosity& av,
                   double sound_speed, const double* x, const double* v, const double* mass, const double* density,
                   const double* sigma_over_rho2, const ArtificialStress& as, const double* R,
                   double* acceleration, std::size_t n) {
  const bool stress = R != nullptr && as.epsilon > 0.0;
  if (kernel == KernelKind::WendlandC2) {
    if (stress)
      momentum_rate_impl<KernelKind::WendlandC2, true>(nl, h, av, sound_speed, x, v, mass, density, sigma_over_rho2,
                                                       as, R, acceleration, n);
    else
      momentum_rate_impl<KernelKind::WendlandC2, false>(nl, h, av, sound_speed, x, v, mass, density,
                                                        sigma_over_rho2, as, R, acceleration, n);
  } else {
    if (stress)
      momentum_rate_impl<KernelKind::CubicSpline, true>(nl, h, av, sound_speed, x, v, mass, density,
                                                        sigma_over_rho2, as, R, acceleration, n);
    else
      momentum_rate_impl<KernelKind::CubicSpline, false>(nl, h, av, sound_speed, x, v, mass, density,
                                                         sigma_over_rho2, as, R, acceleration, n);
  }
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
