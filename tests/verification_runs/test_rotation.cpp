// Verification 2 (docs/verification.md section 2): rigid rotation of a stressed disc.
//
// PrescribedRotation (cases/verification/rotating_disc.json): a disc with a uniform deviatoric
// initial stress is turned rigidly through one revolution (region with prescribed angular
// velocity: the velocity gradient is the exact spin, the particles stay on their circles). An
// objective stress rate must carry the stress with the body: every particle keeps J2 = S:S/2,
// J3 = det S and p = 0. Tolerance 1e-6 relative (J3 and p relative to J2^(3/2) and J2^(1/2)): the
// Hughes-Winget rotation is exactly orthogonal, so only round-off (~1e-15 per step, ~1000 steps)
// and the round-off of the computed spin's symmetric part (D ~ 1e-16 |W|, times 2G/|S| ~ 77)
// remain; 1e-6 leaves room for neither a first-order update S + dt(WS - SW) (which grows |S| by
// (1 + (w dt)^2) per step, 4e-2 per revolution here) nor a D of order dt |w|^2 (1e-1 here).
// Particles where the gradient correction falls back to the plain gradient (gradient_condition
// -1: rim corners of the lattice disc) see L != W and are excluded and counted (docs/verification.md).
// The components must also equal R(w t) S0 R(w t)^T within 1e-4 relative: the Cayley rotation
// turns by 2 atan(w dt/2) per step instead of w dt, a phase lag (w dt)^3/12 per step, 2e-5 rad
// per revolution here.
//
// SpinningDisc (cases/verification/spinning_disc.json): the same disc spinning freely. Linear
// momentum is conserved to round-off (antisymmetric pair forces). Angular momentum is not a
// property of the discretisation: the pair force (sigma_i/rho_i^2 + sigma_j/rho_j^2).grad W_ij is
// not along x_ij when the stress is anisotropic, and the centrifugal stress of a spinning disc is.
// The 1e-6 target is not reachable; the test states the measured change and fails if it grows
// beyond it (a regression bound, not a physical tolerance; docs/verification.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

struct Stress {
  double s[6];
  double p;
  bool corrected;  // gradient_condition >= 0: the corrected gradient (exact for the rigid field) was used
};

std::map<long long, Stress> stresses(const Frame& f) {
  std::map<long long, Stress> out;
  const auto& S = f.arrays.at("deviatoric_stress");
  const auto& p = f.arrays.at("pressure");
  const auto& id = f.arrays.at("id");
  const auto& condition = f.arrays.at("gradient_condition");
  for (std::size_t i = 0; i < f.count; ++i) {
    Stress st{};
    for (int c = 0; c < 6; ++c) st.s[c] = S[6 * i + c];
    st.p = p[i];
    st.corrected = condition[i] >= 0.0;
    out[static_cast<long long>(id[i])] = st;
  }
  return out;
}

double j2(const Stress& t) {
  const double* s = t.s;
  return 0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
}

double j3(const Stress& t) {  // det S, VTK order xx yy zz xy yz xz
  const double* s = t.s;
  return s[0] * (s[1] * s[2] - s[4] * s[4]) - s[3] * (s[3] * s[2] - s[4] * s[5]) + s[5] * (s[3] * s[4] - s[1] * s[5]);
}

TEST(RigidRotation, PrescribedRotationKeepsStressInvariants) {
  const double omega = 2.0 * std::numbers::pi;
  const RunResult r = run_case("rotating_disc.json", "rotating_disc", {});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto files = frames(r.out);
  ASSERT_GE(files.size(), 2u);
  const auto first = stresses(read_frame(files.front())), last = stresses(read_frame(files.back()));
  const json summary = read_summary(r.out);
  const double t_end = summary["simulated_time_s"].get<double>();
  ASSERT_NEAR(t_end, 1.0, 0.01);  // one revolution
  const double c = std::cos(omega * t_end), s = std::sin(omega * t_end);
  double dj2 = 0, dj3 = 0, dp = 0, dcomp = 0, fallback_dj2 = 0;
  std::size_t fallback = 0;
  for (const auto& [id, a] : first) {
    const Stress& b = last.at(id);
    if (!b.corrected) {
      // Too few neighbours span some direction (theory eq. 3b): the plain gradient is used, which
      // is not exact for the rigid field, so D != 0 there. Not a property of the stress rate.
      ++fallback;
      fallback_dj2 = std::max(fallback_dj2, std::abs(j2(b) - j2(a)) / j2(a));
      continue;
    }
    const double scale = std::sqrt(j2(a));
    ASSERT_GT(scale, 0.0);
    dj2 = std::max(dj2, std::abs(j2(b) - j2(a)) / j2(a));
    dj3 = std::max(dj3, std::abs(j3(b) - j3(a)) / (scale * scale * scale));
    dp = std::max(dp, std::abs(b.p - a.p) / scale);
    // Expected: R S0 R^T with R the rotation by w t about z.
    const double xx = a.s[0], yy = a.s[1], xy = a.s[3];
    const double exx = c * c * xx - 2 * c * s * xy + s * s * yy, eyy = s * s * xx + 2 * c * s * xy + c * c * yy;
    const double exy = c * s * (xx - yy) + (c * c - s * s) * xy;
    for (double d : {b.s[0] - exx, b.s[1] - eyy, b.s[3] - exy, b.s[2] - a.s[2]}) dcomp = std::max(dcomp, std::abs(d) / scale);
  }
  char line[400];
  std::snprintf(line, sizeof line,
                "rotating_disc: %zu particles, %lld steps, one revolution: max relative change of J2 %.3e, of J3 %.3e, "
                "of p %.3e; max component deviation from R S0 R^T %.3e; %zu particles on the plain-gradient "
                "fallback (excluded; their J2 changed by up to %.3g)\n",
                first.size(), summary["steps"].get<long long>(), dj2, dj3, dp, dcomp, fallback, fallback_dj2);
  std::printf("%s", line);
  record("verification_results.txt", line);
  EXPECT_LT(dj2, 1e-6) << line;
  EXPECT_LT(dj3, 1e-6) << line;
  EXPECT_LT(dp, 1e-6) << line;
  EXPECT_LT(dcomp, 1e-4) << line;
  EXPECT_LT(fallback, first.size() / 4) << line;  // the check must cover most of the disc
}

struct SpinResult {
  double dp = 0, dh = 0;
  std::string line;
};

SpinResult spin(const std::string& tag, const std::vector<std::string>& sets) {
  SpinResult out;
  const RunResult r = run_case("spinning_disc.json", tag, sets);
  EXPECT_EQ(r.code, 0) << r.err;
  const History h = read_history(r.out / "history.csv");
  const json summary = read_summary(r.out);
  const auto& hz = h["angular_momentum_z_kg_m2_s"];
  const auto& px = h["momentum_x_kg_m_s"];
  const auto& py = h["momentum_y_kg_m_s"];
  const auto& pz = h["momentum_z_kg_m_s"];
  // Scale of the linear momentum: sum m |v| >= 2 KE / v_max, v_max = w R.
  const double omega = 2.0 * std::numbers::pi, radius = 0.05;
  const double momentum_scale = 2.0 * h["kinetic_energy_J"].front() / (omega * radius);
  for (std::size_t k = 0; k < h.rows; ++k) {
    out.dp = std::max(out.dp, std::hypot(px[k] - px[0], py[k] - py[0], pz[k] - pz[0]) / momentum_scale);
    out.dh = std::max(out.dh, std::abs(hz[k] - hz[0]) / std::abs(hz[0]));
  }
  char line[300];
  std::snprintf(line, sizeof line,
                "spinning_disc (%s): %lld particles, %lld steps, one revolution: linear momentum max change %.3e of "
                "sum m|v|; angular momentum max relative change %.3e\n",
                tag.c_str(), summary["particles"].get<long long>(), summary["steps"].get<long long>(), out.dp, out.dh);
  out.line = line;
  std::printf("%s", line);
  record("verification_results.txt", line);
  return out;
}

// Free spinning disc, one revolution. The corrected momentum equation (theory eq. 7) exerts no net
// torque wherever the kernel correction holds (sum_j V_j x_ij (x) C grad W = -I with sigma
// symmetric), the viscosity and the artificial stress (eq. 9, projected on the pair direction) are
// central, and the leapfrog update conserves angular momentum for torque-free forces: angular and
// linear momentum are conserved to round-off with and without artificial stress. Tolerance 1e-12
// (measured 1.5e-15 without, 1.4e-15 with): far below the 1e-6, and a non-central
// pair term anywhere (as the tensor form of eq. 9 was: 5.9e-6) fails it.
TEST(RigidRotation, FreeSpinningDiscMomentum) {
  const SpinResult plain = spin("spinning_disc_no_as", {"numerics.artificial_stress.epsilon=0"});
  EXPECT_LT(plain.dp, 1e-12) << plain.line;
  EXPECT_LT(plain.dh, 1e-12) << plain.line;
  const SpinResult with_as = spin("spinning_disc", {});
  EXPECT_LT(with_as.dp, 1e-12) << with_as.line;
  EXPECT_LT(with_as.dh, 1e-12) << with_as.line;
}

// The same with the second-order gradient correction (docs/theory.md section 18): its momentum term
// (eq. 136) is the dual of a gradient exact for linear fields, so it exerts no net torque either
// (eq. 137). Same tolerance and reason as above.
TEST(RigidRotation, FreeSpinningDiscMomentumSecondOrderGradient) {
  const SpinResult second = spin("spinning_disc_second_order", {"numerics.gradient_correction_order=second"});
  EXPECT_LT(second.dp, 1e-12) << second.line;
  EXPECT_LT(second.dh, 1e-12) << second.line;
}

// The deviatoric-only correction (numerics.momentum_correction = deviatoric, theory eq. 7b): its pressure
// part is the plain -p I, a central pair force, and S C's torque sums to -sum_i V_i eps : S_i = 0 as for
// eq. 7, so the pair forces exert no net torque either (the fully plain term, eq. 7a, loses 1.4e-4 per
// revolution here: docs/verification.md 5b). Same tolerance and reason as above.
TEST(RigidRotation, FreeSpinningDiscMomentumDeviatoricCorrection) {
  const SpinResult dev = spin("spinning_disc_deviatoric", {"numerics.momentum_correction=deviatoric"});
  EXPECT_LT(dev.dp, 1e-12) << dev.line;
  EXPECT_LT(dev.dh, 1e-12) << dev.line;
}

}  // namespace
