#include "engine/sph_operators.hpp"

#include <cmath>

namespace sphforge {

namespace {
// Symmetric 6-component storage (xx yy zz xy yz xz) <-> 3x3 index.
constexpr int kSym[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};

template <KernelKind K>
void velocity_gradient_impl(const NeighbourList& nl, double h, const double* x, const double* v, const double* m,
                            const double* rho, double* L, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double l[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    const double vi[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    for (const std::uint32_t* p = nl.begin(i); p != nl.end(i); ++p) {
      const std::size_t j = *p;
      const double xij[3] = {xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]};
      const double r = std::sqrt(xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2]);
      const double f = kernel_gradient_factor(K, r, h) * m[j] / rho[j];  // V_j (dW/dr)/r
      const double dv[3] = {v[3 * j] - vi[0], v[3 * j + 1] - vi[1], v[3 * j + 2] - vi[2]};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) l[3 * a + b] += dv[a] * f * xij[b];
    }
    for (int c = 0; c < 9; ++c) L[9 * i + c] = l[c];
  }
}

template <KernelKind K>
void momentum_rate_impl(const NeighbourList& nl, double h, const ArtificialViscosity& av, double c0,
                        const double* x, const double* v, const double* m, const double* rho, const double* p,
                        const double* S, double* acc, std::size_t n) {
  const double eta2h2 = av.eta * av.eta * h * h;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    const double vi[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    const double inv_rho_i2 = 1.0 / (rho[i] * rho[i]);
    double si[6];
    for (int c = 0; c < 6; ++c) si[c] = S[6 * i + c] * inv_rho_i2;
    const double pi = p[i] * inv_rho_i2;
    double a[3] = {0, 0, 0};
    for (const std::uint32_t* q = nl.begin(i); q != nl.end(i); ++q) {
      const std::size_t j = *q;
      const double xij[3] = {xi[0] - x[3 * j], xi[1] - x[3 * j + 1], xi[2] - x[3 * j + 2]};
      const double r2 = xij[0] * xij[0] + xij[1] * xij[1] + xij[2] * xij[2];
      const double gw = kernel_gradient_factor(K, std::sqrt(r2), h);  // grad_i W_ij = gw * x_ij
      const double inv_rho_j2 = 1.0 / (rho[j] * rho[j]);
      // sigma/rho^2 summed over the pair, sigma = S - p I  (eq. 7)
      double t[6];
      for (int c = 0; c < 6; ++c) t[c] = si[c] + S[6 * j + c] * inv_rho_j2;
      const double pp = pi + p[j] * inv_rho_j2;
      t[0] -= pp;
      t[1] -= pp;
      t[2] -= pp;
      // Monaghan artificial viscosity, only for approaching pairs  (eq. 8)
      const double vij_xij = (vi[0] - v[3 * j]) * xij[0] + (vi[1] - v[3 * j + 1]) * xij[1] +
                             (vi[2] - v[3 * j + 2]) * xij[2];
      if (vij_xij < 0.0) {
        const double mu = h * vij_xij / (r2 + eta2h2);
        const double rho_bar = 0.5 * (rho[i] + rho[j]);
        const double Pi = (-av.alpha * c0 * mu + av.beta * mu * mu) / rho_bar;
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
                       const double* mass, const double* density, double* L, std::size_t n) {
  if (kernel == KernelKind::WendlandC2)
    velocity_gradient_impl<KernelKind::WendlandC2>(nl, h, x, v, mass, density, L, n);
  else
    velocity_gradient_impl<KernelKind::CubicSpline>(nl, h, x, v, mass, density, L, n);
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

void momentum_rate(const NeighbourList& nl, KernelKind kernel, double h, const ArtificialViscosity& av,
                   double sound_speed, const double* x, const double* v, const double* mass, const double* density,
                   const double* pressure, const double* deviatoric_stress, double* acceleration, std::size_t n) {
  if (kernel == KernelKind::WendlandC2)
    momentum_rate_impl<KernelKind::WendlandC2>(nl, h, av, sound_speed, x, v, mass, density, pressure,
                                               deviatoric_stress, acceleration, n);
  else
    momentum_rate_impl<KernelKind::CubicSpline>(nl, h, av, sound_speed, x, v, mass, density, pressure,
                                                deviatoric_stress, acceleration, n);
}

}  // namespace sphforge
