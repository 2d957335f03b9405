// The contact pass (core/src/engine/contact.cpp, docs/theory.md section 3): its cell culling finds
// exactly the particles a brute-force distance test finds, and the tool's reaction is minus the
// sum of the contact forces (Newton's third law, torque about z included). The friction laws'
// memory (eq. 18b), kept by the pass for the touching particles only and keyed by particle id,
// follows a particle through reordering and is forgotten when it leaves the contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <tuple>
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
  // With its per-particle indices in lent storage (the pass scratch in a run: 12 bytes per
  // particle) the pass finds the same contacts and forces, to the bit, and holds 12 n bytes less.
  PenaltyContact lent;
  lent.configure(settings, {nullptr, nullptr}, dx, 1e9);
  std::vector<double> f2(3 * n, 0.0), storage((3 * n * sizeof(std::uint32_t) + 7) / 8, 0.0);
  a.force = f2.data();
  a.borrow = storage;
  EXPECT_EQ(lent.apply(tools, a), found);
  EXPECT_EQ(f2, f);
  EXPECT_EQ(lent.bytes() + 3 * n * sizeof(std::uint32_t), contact.bytes());
  // With as much lent storage as a run's pass scratch (7 doubles per particle, filled with NaN so
  // that a value read before it is written would show) the near cells' query and the law's batch
  // live there too: the same contacts and forces to the bit, and the pass holds less than with the
  // indices alone (what stays: culling cells, near and touching particle lists).
  PenaltyContact roomy;
  roomy.configure(settings, {nullptr, nullptr}, dx, 1e9);
  std::vector<double> f3(3 * n, 0.0), scratch(7 * n, std::numeric_limits<double>::quiet_NaN());
  a.force = f3.data();
  a.borrow = scratch;
  EXPECT_EQ(roomy.apply(tools, a), found);
  EXPECT_EQ(f3, f);
  const std::size_t near_and_batch = lent.bytes() - roomy.bytes();
  EXPECT_GT(roomy.bytes(), 0u);
  EXPECT_LT(roomy.bytes(), lent.bytes());
  // The law's batch alone is 26 doubles per contact of the tool with the most (the arrays are
  // sized per tool and reused); the near cells' query adds 7 per near particle.
  std::size_t most = 0;
  for (std::size_t t = 0; t < 2; ++t) most = std::max(most, lent.tool_stats()[t].contacts);
  EXPECT_GE(near_and_batch, 26 * sizeof(double) * most);
}

// A law that only counts, in its memory, the passes a particle has touched for (x component) and
// records the particle's current index (y component): what the pass keeps between calls is then visible.
struct CountingLaw : ContactLaw {
  bool needs_history() const override { return true; }
  void tangential_forces(ContactBatch& b) const override {
    for (std::size_t c = 0; c < b.count; ++c) {
      b.history[3 * c] += 1.0;
      b.history[3 * c + 1] = static_cast<double>(b.particle[c]);
    }
  }
};

TEST(ContactPass, FrictionMemoryFollowsTheParticleIdAndIsForgottenOffContact) {
  const double dx = 1e-3;
  std::vector<RigidTool> tools;
  tools.emplace_back("die", std::vector<Eigen::Vector2d>{{0.0, 0.0}, {10e-3, 0.0}});  // z = 0, workpiece above
  CountingLaw law;
  PenaltyContact contact;
  contact.configure(ContactSettings{}, {&law}, dx, 1e9);
  // Four particles, ids 10..13; 12 hovers 5 dx above the die, the others touch it (z < dx/2).
  std::vector<double> x = {1e-3, 0, 0.2e-3, 2e-3, 0, 0.3e-3, 3e-3, 0, 5e-3, 4e-3, 0, 0.1e-3};
  std::vector<std::int64_t> id = {10, 11, 12, 13};
  const std::size_t n = 4;
  std::vector<double> v(3 * n, 0.0), m(n, 1e-6), acc(3 * n, 0.0), f(3 * n, 0.0);
  auto pass = [&] {
    ContactArrays a;
    a.x = x.data();
    a.v = v.data();
    a.mass = m.data();
    a.acceleration = acc.data();
    a.id = id.data();
    a.n = n;
    a.dt = 1e-7;
    a.force = f.data();
    return contact.apply(tools, a);
  };
  // (id, count of passes in contact, index at the last pass), ascending ids. Exact: small integers.
  using Entry = std::tuple<std::int64_t, double, double>;
  auto memory = [&] {
    std::vector<Entry> out;
    for (const FrictionHistoryEntry& e : contact.friction_history(0)) out.emplace_back(e.id, e.value[0], e.value[1]);
    return out;
  };
  EXPECT_EQ(pass(), 3u);
  EXPECT_EQ(memory(), (std::vector<Entry>{{10, 1, 0}, {11, 1, 1}, {13, 1, 3}}));
  // Reordering (as the Morton sort does): the arrays reversed, the memory follows the ids.
  std::reverse(id.begin(), id.end());
  for (std::size_t i = 0; i < n / 2; ++i)
    for (int d = 0; d < 3; ++d) std::swap(x[3 * i + d], x[3 * (n - 1 - i) + d]);
  EXPECT_EQ(pass(), 3u);
  EXPECT_EQ(memory(), (std::vector<Entry>{{10, 2, 3}, {11, 2, 2}, {13, 2, 0}}));
  // Particle 11 (now index 2) leaves the die: its memory goes (eq. 18b), and restarts from zero
  // when it comes back.
  x[3 * 2 + 2] = 5e-3;
  EXPECT_EQ(pass(), 2u);
  EXPECT_EQ(memory(), (std::vector<Entry>{{10, 3, 3}, {13, 3, 0}}));
  x[3 * 2 + 2] = 0.3e-3;
  EXPECT_EQ(pass(), 3u);
  EXPECT_EQ(memory(), (std::vector<Entry>{{10, 4, 3}, {11, 1, 2}, {13, 4, 0}}));
  // The dense form for the outputs: 3 per particle index, zero for the particle not touching.
  std::vector<double> dense(3 * n, -1.0);
  contact.friction_history_dense(0, id.data(), n, dense.data());
  EXPECT_EQ(dense, (std::vector<double>{4, 0, 0, 0, 0, 0, 1, 2, 0, 4, 3, 0}));
  // No contact at all: everything forgotten.
  for (std::size_t i = 0; i < n; ++i) x[3 * i + 2] = 5e-3;
  EXPECT_EQ(pass(), 0u);
  EXPECT_TRUE(contact.friction_history(0).empty());
}


// A law that holds every contact on its wall whatever the force (kinematic sticking, eq. 18j).
struct HoldingLaw : ContactLaw {
  void tangential_forces(ContactBatch& b) const override {
    for (std::size_t c = 0; c < b.count; ++c) {
      sticking_force(b, c, b.tangential_force + 3 * c);
      b.sticking[c] = kHeldOnWall;
    }
  }
};

TEST(ContactPass, ParticleHeldByTwoToolsEndsAtTheLastToolsTangentialVelocity) {
  // A particle in the corner of a fixed barrel (r = 10 mm, the first tool) and a die face z = 0
  // turning at omega (the second), both holding it kinematically. The sticking force is
  // f = -m (v_t / dt + a_other,t) (eq. 18a), where a_other must include the force the barrel has
  // already put on the particle in this pass: then the die's hold, applied last, leaves the
  // particle with the die's velocity in the die's plane, v' = v + dt (a + f_total / m) = v_die.
  // Counting only the internal acceleration, the shared (azimuthal) direction is held twice and
  // v'_theta = v_die - v_theta: 70 % of the die's speed here.
  const double dx = 1e-3;
  std::vector<RigidTool> tools;
  tools.emplace_back("barrel", std::vector<Eigen::Vector2d>{{10e-3, 0.0}, {10e-3, 20e-3}});
  tools.emplace_back("die", std::vector<Eigen::Vector2d>{{0.0, 0.0}, {10e-3, 0.0}});
  tools[1].angular_velocity_rad_s = 50.0;
  HoldingLaw law;
  PenaltyContact contact;
  contact.configure(ContactSettings{}, {&law, &law}, dx, 1e9);
  const double r = 10e-3 - 0.3 * dx;
  std::vector<double> x = {r, 0.0, 0.3 * dx};
  const Eigen::Vector3d v_die = tools[1].surface_velocity(Eigen::Vector3d(x[0], x[1], x[2]));
  ASSERT_GT(v_die.norm(), 0.4);  // omega r = 0.49 m/s, along +y
  // Moving at 30 % of the die's speed, drifting outwards and up, with an internal acceleration.
  std::vector<double> v = {0.05, 0.3 * v_die.y(), 0.02}, m = {1e-3}, acc = {3.0, -2.0, 1.0}, f(3, 0.0);
  ContactArrays a;
  a.x = x.data();
  a.v = v.data();
  a.mass = m.data();
  a.acceleration = acc.data();
  a.n = 1;
  a.dt = 1e-6;
  a.force = f.data();
  ASSERT_EQ(contact.apply(tools, a), 2u);  // one contact with each tool
  double v_new[3];
  for (int d = 0; d < 3; ++d) v_new[d] = v[d] + a.dt * (acc[d] + f[d] / m[0]);
  // In the die's plane (x, y) the particle moves with the die; 1e-12 m/s is round-off of
  // forces of size m |v| / dt = 0.5 N times dt / m = 1e-3.
  EXPECT_NEAR(v_new[0], v_die.x(), 1e-12);
  EXPECT_NEAR(v_new[1], v_die.y(), 1e-12);
}

}  // namespace
