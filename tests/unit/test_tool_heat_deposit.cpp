// The tools' share of the friction heat into their attached thermal particles
// (core/src/engine/tool_heat.cpp, docs/theory.md eq. 91): kernel-weighted among the tool's
// particles within the support of the contact particle, the nearest one when none is, other
// bodies untouched, and the deposited heat equal to the record's to round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/tool_heat.hpp"

using namespace sphforge;

namespace {

struct Scene {
  std::vector<double> x, m;
  std::vector<std::int64_t> body;
  std::vector<BodyRange> bodies;
  NeighbourList nl;
};

constexpr double kDx = 1e-3, kH = 1.3e-3, kS = 4.0;  // s: mass scaling (masses are s times physical)

// Particle 0: the workpiece particle in contact (body 0). Body 1 (attached to tool 0): particles
// at 1, 1.5 and 2.3 dx from it (the support is 2h = 2.6 dx) and one at 3 dx (outside). Body 2
// (attached to tool 1): one particle at 1.2 dx, and one far away at 10 dx.
Scene make_scene() {
  Scene s;
  auto add = [&](double px, double py, double pz, std::int64_t b, double mass) {
    s.x.insert(s.x.end(), {px, py, pz});
    s.m.push_back(mass);
    s.body.push_back(b);
  };
  add(0, 0, 0, 0, 1e-6);
  add(0, 0, kDx, 1, 8e-6);
  add(1.5 * kDx, 0, 0, 1, 9e-6);
  add(0, 2.3 * kDx, 0, 1, 8e-6);
  add(0, 0, -3 * kDx, 1, 8e-6);
  add(-1.2 * kDx, 0, 0, 2, 7e-6);
  add(10 * kDx, 0, 0, 2, 7e-6);
  BodyRange work{"work", 0, 1, kDx, 0, true, -1}, die{"die", 1, 4, kDx, 0, false, 0},
      ram{"ram", 5, 2, kDx, 0, false, 1};
  s.bodies = {work, die, ram};
  s.nl.build(s.x.data(), s.m.size(), kernel_support_radius(kH));
  return s;
}

TEST(ToolHeatDeposit, KernelWeightedAmongTheToolsParticlesWithinTheSupport) {
  Scene s = make_scene();
  std::vector<double> source(s.m.size(), 0.0);
  const double Q = 7.0;
  deposit_tool_heat({{0, 0, Q}}, s.nl, KernelKind::CubicSpline, kH, s.x.data(), s.m.data(), kS, s.body.data(),
                    s.bodies, source.data(), s.m.size(), nullptr);
  // Heat in W of each particle: source (W/kg) x physical mass m / s.
  std::vector<double> q(s.m.size());
  for (std::size_t j = 0; j < q.size(); ++j) q[j] = source[j] * s.m[j] / kS;
  const double w1 = kernel_value(KernelKind::CubicSpline, kDx, kH),
               w2 = kernel_value(KernelKind::CubicSpline, 1.5 * kDx, kH),
               w3 = kernel_value(KernelKind::CubicSpline, 2.3 * kDx, kH);
  // Tolerances 1e-15 relative: one division and one product per particle.
  EXPECT_NEAR(q[1], Q * w1 / (w1 + w2 + w3), 1e-15 * Q);
  EXPECT_NEAR(q[2], Q * w2 / (w1 + w2 + w3), 1e-15 * Q);
  EXPECT_NEAR(q[3], Q * w3 / (w1 + w2 + w3), 1e-15 * Q);
  EXPECT_GT(q[3], 0.0);  // 2.3 dx lies inside the support
  EXPECT_EQ(q[4], 0.0);  // outside the support
  EXPECT_EQ(q[0], 0.0);  // the workpiece particle itself
  EXPECT_EQ(q[5], 0.0);  // another tool's particle, although within the support
  EXPECT_EQ(q[6], 0.0);
  // Energy: the sum deposited is Q (tolerance 4 ulps: three terms summed).
  EXPECT_NEAR(q[1] + q[2] + q[3], Q, 4e-16 * Q);
}

TEST(ToolHeatDeposit, NearestToolParticleTakesAllWhenNoneIsWithinTheSupport) {
  Scene s = make_scene();
  // Tool 1's particle at 1.2 dx moved away to 5 dx: none of tool 1 within the support, the nearer
  // of its two (5 dx against 10 dx) takes everything.
  s.x[3 * 5] = -5 * kDx;
  s.nl.build(s.x.data(), s.m.size(), kernel_support_radius(kH));
  std::vector<double> source(s.m.size(), 0.0);
  const double Q = 3.0;
  deposit_tool_heat({{1, 0, Q}}, s.nl, KernelKind::CubicSpline, kH, s.x.data(), s.m.data(), kS, s.body.data(),
                    s.bodies, source.data(), s.m.size(), nullptr);
  EXPECT_NEAR(source[5] * s.m[5] / kS, Q, 1e-15 * Q);  // one product and one division
  for (std::size_t j = 0; j < source.size(); ++j)
    if (j != 5) EXPECT_EQ(source[j], 0.0) << j;
}

}  // namespace
