// The contact pass (core/src/engine/contact.cpp, docs/theory.md section 3): its cell culling finds
// exactly the particles a brute-force distance test finds, and the tool's reaction is minus the
// sum of the contact forces (Newton's third law, torque about z included).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/contact.hpp"

using namespace sphforge;

namespace {

TEST(ContactPass, CullingFindsExactlyTheTouchingParticles) {
  const double dx = 1e-3;
  // A barrel wall r = 10 mm walked upwards (workpiece inside) and a flat die z = 0 walked outwards
  // (workpiece above), as the ram-extrusion process builds them (tool.hpp conventions).
  std::vector<RigidTool> tools;
  tools.emplace_back("barrel", std::vector<Eigen::Vector2d>{{10e-3, 0.0}, {10e-3, 20e-3}});
  tools.emplace_back("die", std::vector<Eigen::Vector2d>{{0.0, 0.0}, {10e-3, 0.0}});
  tools[1].angular_velocity_rad_s = 3.0;
  // Random particles filling the barrel, some penetrating its walls by up to 0.4 dx (inside the
  // tools' bounds + dx/2, where the pass looks), crowded near the die.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 5000;
  std::vector<double> x(3 * n), v(3 * n), m(n, 1e-6), acc(3 * n, 0.0), f(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 10.4e-3 * std::sqrt(u(rng)), t = 2 * M_PI * u(rng);
    x[3 * i] = r * std::cos(t);
    x[3 * i + 1] = r * std::sin(t);
    x[3 * i + 2] = -0.4e-3 + 20.8e-3 * u(rng) * u(rng);
    for (int d = 0; d < 3; ++d) v[3 * i + d] = 0.1 * (u(rng) - 0.5);
  }
  PenaltyContact contact;
  ContactSettings settings;
  contact.configure(settings, {nullptr, nullptr}, dx, 1e9);
  ContactArrays a;
  a.x = x.data();
  a.v = v.data();
  a.mass = m.data();
  a.acceleration = acc.data();
  a.n = n;
  a.dt = 1e-7;
  a.force = f.data();
  a.history = {nullptr, nullptr};
  const std::size_t found = contact.apply(tools, a);

  // Brute force: every particle asks every tool.
  std::size_t expected = 0;
  std::vector<double> g(3 * n, 0.0);
  Eigen::Vector3d reaction[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  double torque[2] = {0.0, 0.0};
  for (std::size_t t = 0; t < 2; ++t)
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::Vector3d nrm;
      const Eigen::Vector3d xi(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
      const double d = tools[t].signed_distance(xi, nrm);
      if (!(d < 0.5 * dx)) continue;
      ++expected;
      const Eigen::Vector3d vrel = Eigen::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]) - tools[t].surface_velocity(xi);
      const double fn = std::max(0.0, contact.stiffness() * (0.5 * dx - d) -
                                          2 * settings.damping_ratio * std::sqrt(contact.stiffness() * m[i]) * vrel.dot(nrm));
      for (int k = 0; k < 3; ++k) g[3 * i + k] += fn * nrm[k];
      reaction[t] -= fn * nrm;
      torque[t] -= xi.x() * fn * nrm.y() - xi.y() * fn * nrm.x();
    }
  EXPECT_EQ(found, expected);
  EXPECT_GT(expected, 300u);  // the walls are well populated
  // Same forces on every particle (same arithmetic in another order of summation: 1e-12).
  for (std::size_t k = 0; k < 3 * n; ++k) ASSERT_NEAR(f[k], g[k], 1e-12 * (1.0 + std::abs(g[k]))) << k;
  for (std::size_t t = 0; t < 2; ++t) {
    EXPECT_NEAR((tools[t].reaction_force_N - reaction[t]).norm(), 0.0, 1e-12 * (1.0 + reaction[t].norm()));
    EXPECT_NEAR(tools[t].reaction_torque_Nm, torque[t], 1e-12 * (1.0 + std::abs(torque[t])));
    EXPECT_EQ(contact.tool_stats()[t].contacts > 0, true);
  }
}

}  // namespace
