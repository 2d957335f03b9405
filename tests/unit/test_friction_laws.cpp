// Friction-law plugins at a single contact (docs/verification.md section 11, items 3-5; docs/theory.md
// eqs. 18-18h): the law is loaded from the real plugin, handed a batch of one contact and driven by
// the same leapfrog update the core uses, v^{n+1/2} = v^{n-1/2} + dt (a_other + f_t/m).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "sphforge/contact_law.hpp"
#include "sphforge/parameters.hpp"
#include "sphforge/plugin.hpp"
#include "sphforge/plugin_loader.hpp"

using namespace sphforge;
using nlohmann::json;

namespace {

/// The loader must outlive the law (the law's code lives in the loaded library).
struct LoadedLaw {
  PluginLoader loader{{std::filesystem::path(SPHFORGE_PLUGIN_BUILD_DIR)}};
  std::unique_ptr<ContactLaw> law;
  explicit LoadedLaw(const json& section) {
    const LoadedPlugin& p = loader.load(PluginKind::Contact, section["plugin"].get<std::string>());
    law = p.descriptor->make_contact(
        validate_parameters(section, p.descriptor->parameters, "test.json", "/contact/law", {"plugin"}));
  }
};

/// One contact on a wall at rest with normal +z.
struct OneContact {
  double mass = 1.0, fn = 0.0, gap = 0.0, vn = 0.0, damping = 0.0, area = 1e-6, yield = 1e300;
  double normal[3] = {0, 0, 1}, vt[3] = {0, 0, 0}, acc[3] = {0, 0, 0}, history[3] = {0, 0, 0};
  double ft[3] = {0, 0, 0}, sticking = 0.0;
  std::size_t particle = 0;
  ContactBatch batch(double dt, double stiffness) {
    ContactBatch b;
    b.count = 1;
    b.dt = dt;
    b.stiffness = stiffness;
    b.particle = &particle;
    b.mass = &mass;
    b.normal = normal;
    b.normal_force = &fn;
    b.penetration = &gap;
    b.normal_velocity = &vn;
    b.damping = &damping;
    b.tangential_velocity = vt;
    b.acceleration = acc;
    b.contact_area = &area;
    b.yield_stress = &yield;
    b.history = history;
    b.tangential_force = ft;
    b.sticking = &sticking;
    return b;
  }
};

// Item 3: stick-slip with an exact solution (Potra, Anitescu, Gavrea & Trinkle 2006): m = 1 kg,
// mu = 0.8, g = 9.81 m/s^2, F_x = 8 cos(t) N, x0 = 3 m. Slides until t = 0.338608 s, sticks at
// x0 + 4.34857 mm, slides back between 2.946347 s and 3.532835 s by -13.0457 mm.
// Tolerance (issue): 1 % of the displacement scale (4.34857 mm) for x, 1 % of the velocity scale
// (the largest speed of the first slip, 0.019797 m/s at cos t = 7.848/8) for v. The elastic
// sticking spring (k_t = 1e6 N/m here) deflects by up to 8 N / k_t = 8 um = 0.18 % of the
// displacement scale, and dt = 1e-4 s resolves the slip phases to 0.03 % of their length.
TEST(FrictionLaws, CoulombStickSlipPotra) {
  LoadedLaw law(json{{"plugin", "coulomb"}, {"friction_coefficient", 0.8}});
  ASSERT_TRUE(law.law->needs_history());
  OneContact c;
  const double g = 9.81, dt = 1e-4, k = 1e6;
  c.fn = c.mass * g;
  double x = 3.0, v = 0.0, t = 0.0;
  double x2 = 0, v015 = 0, x4 = 0;
  const long steps = std::lround(4.0 / dt);
  for (long s = 0; s <= steps; ++s) {
    // x and t at integer steps, v at half steps: v(t) is the mean of the two half steps.
    const double a_other = 8.0 * std::cos(t) / c.mass;
    c.vt[0] = v;
    c.acc[0] = a_other;
    ContactBatch b = c.batch(dt, k);
    law.law->tangential_forces(b);
    const double v_new = v + dt * (a_other + c.ft[0] / c.mass);
    if (s == std::lround(2.0 / dt)) x2 = x;
    if (s == std::lround(0.15 / dt)) v015 = 0.5 * (v + v_new);
    if (s == std::lround(4.0 / dt)) x4 = x;
    v = v_new;
    x += dt * v;
    t += dt;
  }
  const double dscale = 4.34857e-3, vscale = 0.019797;
  const double ex2 = (x2 - 3.0043486) / dscale, ev = (v015 - 0.018305) / vscale,
               ex4 = (x4 - (3.0043486 - 0.0130457)) / dscale;
  char line[300];
  std::snprintf(line, sizeof line,
                "coulomb stick-slip: x(2 s) = %.7f m (error %+.3f %% of 4.34857 mm), v(0.15 s) = %.6f m/s (%+.3f %% "
                "of 0.019797 m/s), x(4 s) = %.7f m (%+.3f %%)\n",
                x2, 100 * ex2, v015, 100 * ev, x4, 100 * ex4);
  std::printf("%s", line);
  EXPECT_LT(std::abs(ex2), 0.01) << line;
  EXPECT_LT(std::abs(ev), 0.01) << line;
  EXPECT_LT(std::abs(ex4), 0.01) << line;
}

// A sliding contact decelerates at exactly mu f_n / m until it stops; then the spring holds it.
// Tolerance 1e-12 relative on the deceleration: it is mu f_n / m by construction of the return to
// the cone, up to round-off.
TEST(FrictionLaws, CoulombSlidingDecelerationAndStop) {
  LoadedLaw law(json{{"plugin", "coulomb"}, {"friction_coefficient", 0.3}});
  OneContact c;
  c.mass = 2e-3;
  c.fn = c.mass * 9.81;
  const double dt = 1e-5, k = 1e5;
  double v = 0.5;
  c.vt[0] = v;
  ContactBatch b = c.batch(dt, k);
  law.law->tangential_forces(b);
  EXPECT_EQ(c.sticking, 0.0);
  EXPECT_NEAR(c.ft[0] / c.mass, -0.3 * 9.81, 1e-12 * 0.3 * 9.81);
  // Slide to a stop: the stopping distance v0^2 / (2 mu g) within one step's travel (v0 dt).
  double x = 0.0;
  for (int s = 0; s < 200000; ++s) {
    c.vt[0] = v;
    b = c.batch(dt, k);
    law.law->tangential_forces(b);
    v += dt * c.ft[0] / c.mass;
    x += dt * v;
  }
  const double expected = 0.5 * 0.5 / (2 * 0.3 * 9.81);
  // Tolerance: one step's travel v0 dt (where in the step the stop falls) plus the spring's
  // deflection mu f_n / k_t at rest.
  EXPECT_NEAR(x, expected, 0.5 /*v0*/ * dt + 0.3 * c.fn / k) << "stop at " << x << " m, expected " << expected;
  EXPECT_EQ(c.sticking, 1.0);
  EXPECT_LT(std::abs(v), 1e-6);  // at rest: the damped spring has settled
}

// Item 4: Coulomb-Tresca switches from slip to stick exactly where mu f_n reaches
// sigma_y A / sqrt(3). Sweep of the normal force across the switch for a particle sliding at
// 1 m/s (its sticking force, m v / dt = 1e3 N, exceeds both limits): below the switch
// |f_t| = mu f_n and the contact slides; above it |f_t| = sigma_y A / sqrt(3) and it sticks.
// Tolerance: the switch lies within one sweep increment (1e-6 N) of the exact value; the forces
// equal their formulas to 1e-12 relative (round-off).
TEST(FrictionLaws, CoulombTrescaSwitchesWhereMuPReachesTheShearLimit) {
  LoadedLaw law(json{{"plugin", "coulomb_tresca"}, {"friction_coefficient", 0.5}});
  ASSERT_TRUE(law.law->needs_yield_stress());
  OneContact c;
  c.mass = 1e-3;
  c.yield = 2e6;
  c.area = 1e-6;
  const double tresca = 2e6 * 1e-6 / std::sqrt(3.0);  // 1.1547 N
  const double fn_switch = tresca / 0.5;
  double first_stick = -1.0;
  const double step = 1e-6;
  for (double fn = fn_switch - 2e-4; fn < fn_switch + 2e-4; fn += step) {
    c.fn = fn;
    c.vt[0] = 1.0;
    ContactBatch b = c.batch(1e-6, 1e6);
    law.law->tangential_forces(b);
    const double f = std::abs(c.ft[0]);
    if (c.sticking > 0.5) {
      if (first_stick < 0) first_stick = fn;
      EXPECT_NEAR(f, tresca, 1e-12 * tresca);
    } else {
      EXPECT_LT(first_stick, 0.0) << "slides again at " << fn << " N after sticking";
      EXPECT_NEAR(f, 0.5 * fn, 1e-12 * fn);
    }
    EXPECT_LT(c.ft[0], 0.0);  // against the slip
  }
  std::printf("coulomb_tresca: switch at f_n = %.7f N (mu f_n = %.7f N), exact %.7f N (sigma_y A/sqrt3 = %.7f N)\n",
              first_stick, 0.5 * first_stick, fn_switch, tresca);
  EXPECT_GE(first_stick, fn_switch);
  EXPECT_LT(first_stick - fn_switch, step + 1e-12);
}

// Eq. 18j: with sticking "kinematic", a contact in the sticking regime (mu f_n > tau_y A) gets the
// force that makes it move with the wall at the end of the step whatever its size, and is flagged
// kHeldOnWall (no friction heat in the core); in the Coulomb regime the law is unchanged. The
// particle slides at 1 m/s on a wall that also pulls it with a = 50 m/s^2: its sticking force,
// -m (v/dt + a) = -1000.05 N, is far above tau_y A = 1.15 N. Tolerance: round-off (1e-12 relative).
TEST(FrictionLaws, CoulombTrescaKinematicStickingHoldsWhateverTheForce) {
  LoadedLaw kinematic(json{{"plugin", "coulomb_tresca"}, {"friction_coefficient", 0.5}, {"sticking", "kinematic"}});
  LoadedLaw limited(json{{"plugin", "coulomb_tresca"}, {"friction_coefficient", 0.5}});
  const double tresca = 2e6 * 1e-6 / std::sqrt(3.0);
  for (const double fn : {0.5 * tresca, 4.0 * tresca}) {  // Coulomb regime, then sticking regime
    OneContact c, d;
    for (OneContact* k : {&c, &d}) {
      k->mass = 1e-3, k->yield = 2e6, k->area = 1e-6, k->fn = fn;
      k->vt[0] = 1.0, k->acc[0] = 50.0;
    }
    ContactBatch b = c.batch(1e-6, 1e6), e = d.batch(1e-6, 1e6);
    kinematic.law->tangential_forces(b);
    limited.law->tangential_forces(e);
    const double v_end = c.vt[0] + 1e-6 * (c.acc[0] + c.ft[0] / c.mass);
    std::printf("coulomb_tresca kinematic, f_n = %.4f N: f_t = %.6f N (force_limited %.6f N), flag %.0f, end slip %.2e m/s\n",
                fn, c.ft[0], d.ft[0], c.sticking, v_end);
    if (0.5 * fn > tresca) {
      EXPECT_EQ(c.sticking, kHeldOnWall);
      EXPECT_NEAR(c.ft[0], -1e-3 * (1.0 / 1e-6 + 50.0), 1e-12 * 1000.05);
      EXPECT_NEAR(v_end, 0.0, 1e-9);  // moves with the wall (round-off of 1 - 1)
      EXPECT_NEAR(d.ft[0], -tresca, 1e-12 * tresca);  // the default slides at the shear limit
    } else {
      EXPECT_EQ(c.sticking, d.sticking);
      EXPECT_EQ(c.ft[0], d.ft[0]);  // the Coulomb regime is the same law
      EXPECT_NEAR(c.ft[0], -0.5 * fn, 1e-12 * fn);
    }
  }
}

// Item 5 (law): Navier slip. A particle pulled along the wall by a constant force F > tau_0 A
// reaches the slip speed where the wall shear balances it, tau_0 + beta V^n = F / A; the discrete
// update v' = v + dt (F - tau_w(v) A)/m has this speed as its fixed point, so the tolerance is the
// convergence after 5000 relaxation times (1e-9 relative). Below tau_0 A the wall holds the
// particle: the regularisation (eq. 18h) gives exactly zero velocity, no chatter.
TEST(FrictionLaws, NavierSlipSteadySpeedAndRestBelowYield) {
  const double tau0 = 1.8e4, beta = 5.4e5, n = 0.58, area = 1e-6, m = 1e-3;
  LoadedLaw law(json{{"plugin", "navier_slip"}, {"yield_shear_stress", tau0}, {"slip_coefficient", beta},
                     {"slip_exponent", n}});
  for (const double V : {0.001, 0.01, 0.1}) {
    const double F = (tau0 + beta * std::pow(V, n)) * area;
    OneContact c;
    c.mass = m;
    c.area = area;
    const double dt = 1e-5;
    double v = 0.0;
    for (int s = 0; s < 400000; ++s) {
      c.vt[0] = v;
      c.acc[0] = F / m;
      ContactBatch b = c.batch(dt, 1e6);
      law.law->tangential_forces(b);
      v += dt * (F / m + c.ft[0] / m);
    }
    std::printf("navier_slip: V = %.6g m/s reached %.9g m/s\n", V, v);
    EXPECT_NEAR(v, V, 1e-9 * V);
  }
  // Below the yield value: the particle never moves, and its force is exactly the pull's opposite.
  OneContact c;
  c.mass = m;
  c.area = area;
  double v = 0.0;
  const double F = 0.9 * tau0 * area;
  for (int s = 0; s < 1000; ++s) {
    c.vt[0] = v;
    c.acc[0] = F / m;
    ContactBatch b = c.batch(1e-5, 1e6);
    law.law->tangential_forces(b);
    v += 1e-5 * (F / m + c.ft[0] / m);
    ASSERT_EQ(c.sticking, 1.0);
  }
  EXPECT_NEAR(v, 0.0, 1e-15);  // round-off of F/m - F/m
}

}  // namespace
