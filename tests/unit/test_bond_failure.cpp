// Unit tests of the bond rule (docs/theory.md eqs. 111-114, docs/failure.md) on two particles:
// the factor k_ij itself, and the two pair passes (velocity gradient, momentum) with and without
// failed particles, under tension and under compression.
//
// Tolerances: the rule multiplies by exactly 0 or 1, so an intact or compressed pair must give
// the same numbers as the pass without the rule up to the round-off of a different instruction
// mix (the instance with the rule may contract products into FMAs differently): 1e-12 relative.
// A broken pair under tension must contribute exactly nothing (compared with 0 exactly, as the
// viscosity is off for the separating pair and there is no other term).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/bond_failure.hpp"
#include "engine/neighbours.hpp"
#include "engine/simulation.hpp"
#include "engine/sph_operators.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/errors.hpp"
#include "sphforge/fields.hpp"
#include "sphforge/plugin_loader.hpp"

namespace {

using namespace sphforge;

TEST(BondFailure, FactorCutsOnlyFailedPairsUnderTension) {
  const double tension[6] = {100.0, 0, 0, 0, 0, 0};      // sigma_xx > 0
  const double compression[6] = {-100.0, 0, 0, 0, 0, 0};  // sigma_xx < 0
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  // Pair along x: its normal stress is sigma_xx.
  EXPECT_EQ(bond_factor(1.0, 1.0, tension, tension, 1.0, 0.0, 0.0), 0.0);
  EXPECT_EQ(bond_factor(1.0, 1.0, compression, compression, 1.0, 0.0, 0.0), 1.0);
  EXPECT_EQ(bond_factor(1.0, 0.0, tension, tension, 1.0, 0.0, 0.0), 1.0);  // eq. 111: both must have failed
  EXPECT_EQ(bond_factor(0.0, 1.0, tension, tension, 1.0, 0.0, 0.0), 1.0);
  EXPECT_EQ(bond_factor(0.0, 0.0, tension, tension, 1.0, 0.0, 0.0), 1.0);
  // The SUM of the two stresses decides: tension on one side outweighed by compression on the other.
  const double mild[6] = {50.0, 0, 0, 0, 0, 0};
  EXPECT_EQ(bond_factor(1.0, 1.0, mild, compression, 1.0, 0.0, 0.0), 1.0);
  // Zero normal stress is not tension (a stress-free failed body keeps its pairs).
  EXPECT_EQ(bond_factor(1.0, 1.0, zero, zero, 1.0, 0.0, 0.0), 1.0);
  // Only the normal component of the pair counts: tension along x, pair along y -> kept.
  EXPECT_EQ(bond_factor(1.0, 1.0, tension, tension, 0.0, 1.0, 0.0), 1.0);
  // Shear stress: sigma_xy > 0 pulls the diagonal (1, 1) apart and presses (1, -1) together.
  const double shear[6] = {0, 0, 0, 100.0, 0, 0};
  EXPECT_EQ(bond_factor(1.0, 1.0, shear, shear, 1.0, 1.0, 0.0), 0.0);
  EXPECT_EQ(bond_factor(1.0, 1.0, shear, shear, 1.0, -1.0, 0.0), 1.0);
  // Symmetric in i and j and in x_ij -> -x_ij (pair forces stay antisymmetric).
  const double a[6] = {30.0, -80.0, 10.0, 25.0, -5.0, 40.0}, b[6] = {-10.0, 20.0, 5.0, 60.0, 15.0, -35.0};
  for (const std::array<double, 3>& x : {std::array<double, 3>{0.3, -0.7, 0.2}, std::array<double, 3>{-0.5, 0.1, 0.9},
                                         std::array<double, 3>{0.6, 0.6, -0.4}}) {
    const double k = bond_factor(1.0, 1.0, a, b, x[0], x[1], x[2]);
    EXPECT_EQ(k, bond_factor(1.0, 1.0, b, a, x[0], x[1], x[2]));
    EXPECT_EQ(k, bond_factor(1.0, 1.0, a, b, -x[0], -x[1], -x[2]));
  }
}

/// Two particles on the x axis, 0.8 dx apart, moving apart along x (so the viscosity is off).
struct TwoParticles {
  static constexpr std::size_t n = 2;
  double dx = 1e-3, h = 1.3e-3;
  std::vector<double> x = {0.0, 0.0, 0.0, 0.8e-3, 0.0, 0.0};
  std::vector<double> v = {-0.1, 0.02, 0.0, 0.1, -0.03, 0.01};
  std::vector<double> m = std::vector<double>(n, 7.85e-6), rho = std::vector<double>(n, 7850.0);
  std::vector<double> volume = std::vector<double>(n, 1e-9);
  std::vector<double> p, S, sigma, stress_c = std::vector<double>(9 * n);
  std::vector<double> failed;
  NeighbourList nl;

  /// Uniaxial stress sxx along the pair (plus a shear xy), failed flags as given.
  TwoParticles(double sxx, double failed_i, double failed_j) {
    for (std::size_t i = 0; i < n; ++i) {
      p.push_back(-sxx / 3.0);
      const double s[6] = {2.0 * sxx / 3.0, -sxx / 3.0, -sxx / 3.0, 0.2 * std::abs(sxx), 0.0, 0.0};
      S.insert(S.end(), s, s + 6);
    }
    failed = {failed_i, failed_j};
    sigma.resize(6 * n);
    cauchy_stress(p.data(), S.data(), sigma.data(), n);
    corrected_stress(p.data(), S.data(), nullptr, true, stress_c.data(), n);
    nl.build(x.data(), n, kernel_support_radius(h) + 0.2 * h);
  }
  BondFailure rule() const { return {failed.data(), sigma.data()}; }

  std::vector<double> gradient(bool with_rule) const {
    std::vector<double> L(9 * n);
    velocity_gradient(nl, KernelKind::CubicSpline, h, x.data(), v.data(), volume.data(), false, L.data(), nullptr,
                      nullptr, n, with_rule ? rule() : BondFailure{});
    return L;
  }
  std::vector<double> acceleration(bool with_rule) const {
    std::vector<double> a(3 * n);
    ArtificialStress none;
    none.epsilon = 0.0;
    momentum_rate(nl, KernelKind::CubicSpline, h, ArtificialViscosity{}, 5000.0, x.data(), v.data(), m.data(),
                  rho.data(), volume.data(), stress_c.data(), none, nullptr, nullptr, a.data(), n,
                  with_rule ? rule() : BondFailure{});
    return a;
  }
};

double max_abs(const std::vector<double>& a) {
  double worst = 0.0;
  for (double c : a) worst = std::max(worst, std::abs(c));
  return worst;
}

void expect_same(const std::vector<double>& a, const std::vector<double>& b) {
  const double scale = max_abs(a);
  ASSERT_GT(scale, 0.0);  // the pair interacts at all
  for (std::size_t c = 0; c < a.size(); ++c) EXPECT_NEAR(a[c], b[c], 1e-12 * scale) << "component " << c;
}

TEST(BondFailure, BrokenPairUnderTensionLeavesBothPasses) {
  const TwoParticles pair(200e6, 1.0, 1.0);  // both failed, 200 MPa tension along the pair
  const std::vector<double> L0 = pair.gradient(false), a0 = pair.acceleration(false);
  ASSERT_GT(max_abs(L0), 0.0);
  ASSERT_GT(max_abs(a0), 0.0);
  // Without the rule the two particles pull on each other (tension attracts): a_0x > 0, a_1x < 0.
  EXPECT_GT(a0[0], 0.0);
  EXPECT_LT(a0[3], 0.0);
  // With it, the broken bond carries nothing (eqs. 113-114).
  for (double c : pair.gradient(true)) EXPECT_EQ(c, 0.0);
  for (double c : pair.acceleration(true)) EXPECT_EQ(c, 0.0);
}

TEST(BondFailure, BrokenPairUnderCompressionTransmitsEverything) {
  const TwoParticles pair(-200e6, 1.0, 1.0);  // both failed, pressed together: shear stress too
  expect_same(pair.gradient(false), pair.gradient(true));
  const std::vector<double> a = pair.acceleration(true);
  expect_same(pair.acceleration(false), a);
  // The shear stress is transmitted: a y component exists, and the pair forces are opposite.
  EXPECT_NE(a[1], 0.0);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(pair.m[0] * a[d], -pair.m[1] * a[3 + d], 1e-12 * max_abs(a) * pair.m[0]);
}

TEST(BondFailure, PairWithOneIntactParticleIsIntact) {
  const TwoParticles pair(200e6, 1.0, 0.0);  // tension, but only one particle failed (eq. 111)
  expect_same(pair.gradient(false), pair.gradient(true));
  expect_same(pair.acceleration(false), pair.acceleration(true));
}

// The case-file interface (docs/failure.md): the material's failure_plastic_strain switches the
// mechanism on; without it the scene has no `failed` field and no bond_failure pass.
const std::string kBarCase = std::string(SPHFORGE_SOURCE_DIR) + "/cases/verification/notched_bar_failure.json";

bool has_pass(const Simulation& sim, const std::string& name) {
  return std::any_of(sim.passes().begin(), sim.passes().end(), [&](const PassInfo& p) { return p.name == name; });
}

TEST(BondFailure, OnlyAMaterialWithAFailureStrainAddsTheFieldAndThePass) {
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  {
    Simulation sim(load_case(kBarCase, {"material.failure_plastic_strain=0"}), loader);
    EXPECT_FALSE(sim.fields().declared(field::failed));
    EXPECT_FALSE(has_pass(sim, "bond_failure"));
  }
  {
    Simulation sim(load_case(kBarCase, {"material.failure_plastic_strain=0.4"}), loader);
    EXPECT_TRUE(sim.fields().allocated(field::failed));
    EXPECT_TRUE(has_pass(sim, "bond_failure"));
  }
  // johnson_cook takes the same parameter (the shared helper of plugins/materials/common/failure.hpp).
  nlohmann::json doc = nlohmann::json::parse(std::ifstream(kBarCase));
  doc["material"] = {{"plugin", "johnson_cook"},      {"density", "7850 kg/m^3"},
                     {"youngs_modulus", "200 GPa"},   {"poisson_ratio", 0.3},
                     {"A", "300 MPa"},                {"B", "500 MPa"},
                     {"n", 0.3},                      {"reference_temperature", "293 K"},
                     {"melting_temperature", "1800 K"}, {"failure_plastic_strain", 0.4}};
  const std::filesystem::path jc = std::filesystem::current_path() / "bond_failure_johnson_cook.json";
  std::ofstream(jc) << doc.dump(2);
  {
    Simulation sim(load_case(jc.string(), {}), loader);
    EXPECT_TRUE(sim.fields().allocated(field::failed));
    EXPECT_TRUE(has_pass(sim, "bond_failure"));
  }
  {
    Simulation sim(load_case(jc.string(), {"material.failure_plastic_strain=0"}), loader);
    EXPECT_FALSE(sim.fields().declared(field::failed));
  }
}

TEST(BondFailure, NegativeFailureStrainIsAnInputErrorAtItsPointer) {
  PluginLoader loader({SPHFORGE_PLUGIN_BUILD_DIR});
  try {
    Simulation sim(load_case(kBarCase, {"material.failure_plastic_strain=-0.1"}), loader);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), kBarCase);
    EXPECT_EQ(e.pointer(), "/material/failure_plastic_strain");
  }
}

}  // namespace
