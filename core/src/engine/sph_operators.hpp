// The SPH operators of the mechanics pipeline, one function per physics term. Equation
// numbers refer to docs/theory.md. Each acts on whole arrays (SoA, OpenMP over particles).
#pragma once

#include <cstddef>
#include <cstdint>

#include "engine/bond_failure.hpp"
#include "engine/neighbours.hpp"
#include "engine/pair_kernel.hpp"
#include "sphforge/kernels.hpp"

namespace sphforge {

struct ArtificialViscosity {
  double alpha = 1.0;  ///< linear (bulk) term
  double beta = 1.0;   ///< quadratic (von Neumann-Richtmyer) term
  double eta = 0.1;    ///< singularity guard, as a fraction of h
};

/// The pair passes run the best of their generic, AVX2 + FMA and AVX-512VL loops that the CPU has
/// (engine/pair_kernel.hpp). For tests and benchmarks: caps that choice (PairLoopIsa::generic forces
/// the generic loops, PairLoopIsa::avx512vl restores the default). Returns the old cap.
PairLoopIsa limit_pair_loop_isa(PairLoopIsa limit);

/// Particle volume V_i = m_i / rho_i.
void particle_volume(const double* mass, const double* density, double* volume, std::size_t n);

/// Velocity gradient L_i = sum_j V_j (v_j - v_i) (x) grad_i W_ij   (theory eq. 3), optionally with the
/// first-order (Randles-Libersky) correction L_i <- L_i M_i^-1 (eqs. 3a-3b). L stored row-major,
/// 9 per particle, L_ab = dv_a/dx_b. `condition` (may be null) receives the condition number of
/// M_i, or -1 where the correction fell back to the plain gradient. `correction` (may be null; only
/// written when `corrected`) receives C_i = M_i^-1 (6 per particle, symmetric), I on fallback.
/// `failure` (engine/bond_failure.hpp; default: none) leaves out the broken bonds under tension (eq. 113).
/// `h_point` (default null: every pair has h): per-particle smoothing lengths of a scene of several
/// spacings, for every point a list may name; a pair then uses h_ij = (h_i + h_j) / 2 (eq. 138).
void velocity_gradient(const NeighbourList& nl, KernelKind kernel, double h, const double* x, const double* v,
                       const double* volume, bool corrected, double* L, double* condition, double* correction,
                       std::size_t n, const BondFailure& failure = {}, const double* h_point = nullptr);

/// A_i = sigma_i C_i (9 per particle, row-major), sigma = S - p I, the per-particle half of the
/// momentum equation (eq. 7); C null means C = I (no correction, eq. 7a). With correct_pressure false
/// only the deviatoric part is corrected, A_i = S_i C_i - p_i I (eq. 7b).
void corrected_stress(const double* pressure, const double* deviatoric_stress, const double* correction,
                      bool correct_pressure, double* stress_c, std::size_t n);

/// sigma_i / rho_i^2 with sigma = S - p I (6 per particle), the input of the artificial stress.
void stress_over_density_squared(const double* pressure, const double* deviatoric_stress, const double* density,
                                 double* sigma_over_rho2, std::size_t n);

/// Continuity equation: drho_i/dt = -rho_i tr(L_i)   (theory eq. 4)
void continuity_density_rate(const double* L, const double* density, double* density_rate, std::size_t n);

/// Objective (Jaumann) rotation of the deviatoric stress over dt: S <- Q S Q^T with the
/// Hughes-Winget rotation Q = (I - dt Omega/2)^-1 (I + dt Omega/2), Omega = (L - L^T)/2, which
/// integrates dS/dt = Omega S - S Omega to second order and is exactly orthogonal (theory eq. 6)
void jaumann_rotation(const double* L, double dt, double* deviatoric_stress, std::size_t n);

struct ArtificialStress {
  double epsilon = 0.3;   ///< 0 disables the term (and its pass)
  double exponent = 4.0;  ///< n in f_ij = (W(r_ij)/W(dx))^n
  double w_dx = 0.0;      ///< W(dx, h), set by the core from the initial spacing
  /// W(dx / h, 1): the same with h = 1, for variable spacing, where a pair's W(dx_ij, h_ij) is
  /// this / h_ij^3 (eq. 139). Set by the core.
  double w_dx_unit = 0.0;
};

/// Gray-Monaghan-Swift artificial stress R_i (6 per particle, theory eq. 9): in the principal
/// frame of sigma_i, R'_k = -epsilon sigma'_k / rho_i^2 for tensile sigma'_k > 0, else 0.
/// R may be sigma_over_rho2 itself (in place): a particle's six inputs are read before its outputs
/// are written.
void artificial_stress(const double* sigma_over_rho2, double epsilon, double* R, std::size_t n);

/// The particles under principal tension, as a bit set for momentum_rate(): bit i of tension[i / 64]
/// (words of 64 particles, (count + 63) / 64 of them) is set where R_i != 0 (eq. 9). R is negative
/// semidefinite, so it is 0 exactly when its trace is: its diagonal entries are sums of non-positive
/// terms, and a nonzero principal value r_k puts at most r_k / 3 on some diagonal entry (unless
/// |r_k| is so small that this underflows, when the term it would add is below round-off anyway).
/// count covers every point a neighbour list may name (symmetry ghosts included).
void mark_tension(const double* R, std::size_t count, std::uint64_t* tension);

/// Momentum equation in the variationally consistent corrected form (theory eqs. 7-9):
/// a_i = 1/rho_i sum_j V_j (A_i + A_j) . grad_i W_ij  +  sum_j m_j [f_ij^n (R_i + R_j) - Pi_ij I] . grad_i W_ij
/// with A = sigma C from corrected_stress(), Monaghan viscosity Pi_ij and, when R is given, the
/// artificial stress. The stress term is minus the derivative of the stress power sum_i V_i
/// sigma_i : L_i with respect to the velocities, L the corrected gradient: the pair force is
/// antisymmetric (linear momentum exact), angular momentum is exact wherever the correction holds
/// (sum_j V_j x_ij (x) C grad W = -I and sigma symmetric), and the work of the internal forces
/// equals the stress power (energy consistency). `failure` (default: none): broken bonds under tension
/// carry no stress and no artificial stress, the viscosity stays (eq. 114). `tension`: mark_tension()
/// of R; a particle with no tension bit on itself and its neighbours runs its sum without the
/// artificial stress (its terms are exact zeros there; same sums to the bit). Null: every sum has
/// the term.
void momentum_rate(const NeighbourList& nl, KernelKind kernel, double h, const ArtificialViscosity& av,
                   double sound_speed, const double* x, const double* v, const double* mass, const double* density,
                   const double* volume, const double* stress_c, const ArtificialStress& as, const double* R,
                   const std::uint64_t* tension, double* acceleration, std::size_t n,
                   const BondFailure& failure = {}, const double* h_point = nullptr);

}  // namespace sphforge
