// Verification 4 (docs/verification.md section 4): symmetry (docs/theory.md section 11).
//
// cases/verification/spinning_compressed_cylinder.json: an elastic cylinder spinning about z and
// compressed between two rigid z-planes that rotate faster than it (a rotating die: friction drives
// a torsional swirl). The scene is symmetric under rotations by 90 deg about z (the cubic lattice
// with half-integer sites about the axis maps onto itself) and under the mirror z = H/2 (both dies
// move and turn alike). Run in full, as a 90 deg sector, as the sector plus the mid-height mirror
// (an eighth) and as the mirror half alone; at the end time every particle of a reduced run is
// matched with the full run's particle at the same place, and the pressure, sigma_zz, the torsional
// shear S_theta z and the velocity components must agree within 2 % of the full run's range of the
// field (the requirement), the top die's reaction force and torque times the sector count within 2 %.
// The exact discretisation is symmetric, so the runs differ only by round-off (summation orders:
// the ghosts' indices differ from the full run's particles) amplified by the stick-slip contact;
// the measured differences are recorded (verification_results.txt) and are far below 2 %.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

const std::string kCase = "spinning_compressed_cylinder.json";
const std::string kSector = "numerics.symmetry.sector.angle=90 deg";
const std::string kMirror = R"(numerics.symmetry.mirror_planes=[{"point": [0, 0, 0.03], "normal": [0, 0, 1]}])";
// 0.3 s: the dies have closed in by 6 mm (10 % of the height) and turned the billet's ends by
// 0.9 rad against its middle; enough deformation, a third less run time than the case's 0.5 s.
const std::vector<std::string> kShort = {"run.end_time=0.3 s", "run.output_interval=0.3 s"};

struct Quantity {
  std::string name;
  std::function<double(const Frame&, std::size_t)> value;
};

const std::vector<Quantity>& quantities() {
  static const std::vector<Quantity> q = {
      {"pressure", [](const Frame& f, std::size_t i) { return f.arrays.at("pressure")[i]; }},
      {"sigma_zz",
       [](const Frame& f, std::size_t i) { return f.arrays.at("deviatoric_stress")[6 * i + 2] - f.arrays.at("pressure")[i]; }},
      {"S_theta_z",
       [](const Frame& f, std::size_t i) {
         // -sin(theta) S_xz + cos(theta) S_yz: invariant under rotations about z.
         const double* x = &f.arrays.at("position")[3 * i];
         const double* S = &f.arrays.at("deviatoric_stress")[6 * i];
         const double r = std::hypot(x[0], x[1]);
         return r > 0.0 ? (-x[1] * S[5] + x[0] * S[4]) / r : 0.0;
       }},
      {"velocity_x", [](const Frame& f, std::size_t i) { return f.arrays.at("velocity")[3 * i]; }},
      {"velocity_y", [](const Frame& f, std::size_t i) { return f.arrays.at("velocity")[3 * i + 1]; }},
      {"velocity_z", [](const Frame& f, std::size_t i) { return f.arrays.at("velocity")[3 * i + 2]; }},
  };
  return q;
}

Frame last_frame(const fs::path& dir) {
  const auto all = frames(dir);
  if (all.empty()) throw std::runtime_error("no frames in " + dir.string());
  return read_frame(all.back());
}

struct Full {
  Frame frame;
  History history;
  double wall_s = 0.0;
  std::size_t particles = 0;
};

// Bond failure across the cuts (docs/theory.md eqs. 110-114): a soft yield stress and a small failure
// strain, so that most particles fail (3628 of 3792 in the full run) and the body spreads to r = 72 mm;
// the ghosts carry their sources' failed flags and rotated stresses into the pair rule.
const std::vector<std::string> kFailure = {"material.yield_stress=100 Pa", "material.failure_plastic_strain=0.05"};

const Full& full_run(const std::vector<std::string>& extra = {}) {
  static std::map<std::vector<std::string>, Full> cache;
  auto it = cache.find(extra);
  if (it != cache.end()) return it->second;
  const Full& made = cache[extra] = [&] {
    std::vector<std::string> sets = kShort;
    sets.insert(sets.end(), extra.begin(), extra.end());
    const RunResult r = run_case(kCase, extra.empty() ? "symmetry_full" : "symmetry_full_failure", sets);
    if (r.code != 0) throw std::runtime_error("full run failed: " + r.err);
    Full f;
    f.frame = last_frame(r.out);
    f.history = read_history(r.out / "history.csv");
    const json s = read_summary(r.out);
    f.wall_s = s["wall_time_s"].get<double>();
    f.particles = s["particles"].get<std::size_t>();
    return f;
  }();
  return made;
}

/// multiplier: full body over simulated part; tool_factor: the same for the top die's reaction
/// (the sector's N: the mirror z = H/2 leaves the top die wholly on the simulated side).
void compare_with_full(const std::string& label, const std::vector<std::string>& symmetry, double multiplier,
                       double tool_factor, const std::vector<std::string>& extra = {}) {
  const Full& full = full_run(extra);
  std::vector<std::string> sets = kShort;
  sets.insert(sets.end(), extra.begin(), extra.end());
  sets.insert(sets.end(), symmetry.begin(), symmetry.end());
  const RunResult r = run_case(kCase, "symmetry_" + label, sets);
  ASSERT_EQ(r.code, 0) << r.err;
  const json summary = read_summary(r.out);
  ASSERT_TRUE(summary.contains("symmetry"));
  EXPECT_DOUBLE_EQ(summary["symmetry"]["multiplier"].get<double>(), multiplier);
  const std::size_t particles = summary["particles"].get<std::size_t>();
  EXPECT_EQ(particles * static_cast<std::size_t>(multiplier), full.particles);
  const Frame part = last_frame(r.out);
  ASSERT_EQ(part.count, particles);

  // Match every particle of the reduced run with the nearest one of the full run.
  const auto& xf = full.frame.arrays.at("position");
  const auto& xp = part.arrays.at("position");
  std::vector<std::size_t> match(part.count);
  double worst_match = 0.0;
  for (std::size_t i = 0; i < part.count; ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < full.frame.count; ++j) {
      const double d = std::hypot(xp[3 * i] - xf[3 * j], xp[3 * i + 1] - xf[3 * j + 1], xp[3 * i + 2] - xf[3 * j + 2]);
      if (d < best) best = d, match[i] = j;
    }
    worst_match = std::max(worst_match, best);
  }
  const double dx = 5e-3;
  std::string line = "symmetry " + label + ": " + std::to_string(particles) + " of " + std::to_string(full.particles) +
                     " particles, ghosts " + std::to_string(summary["symmetry"]["ghosts"].get<std::size_t>()) +
                     ", wall " + std::to_string(summary["wall_time_s"].get<double>()) + " s (full " +
                     std::to_string(full.wall_s) + " s); worst position match " + std::to_string(worst_match / dx) +
                     " dx; max difference / full range:";
  EXPECT_LT(worst_match, 0.05 * dx) << "a particle of the reduced run has no partner in the full run";
  for (const Quantity& q : quantities()) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t j = 0; j < full.frame.count; ++j) {
      const double v = q.value(full.frame, j);
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < part.count; ++i)
      worst = std::max(worst, std::abs(q.value(part, i) - q.value(full.frame, match[i])));
    const double relative = worst / (hi - lo);
    char text[160];
    std::snprintf(text, sizeof text, " %s %.2e (range %.3g)", q.name.c_str(), relative, hi - lo);
    line += text;
    EXPECT_LT(relative, 0.02) << q.name << ": " << line;
  }
  // Tool reactions: a sector's tool carries 1/N of the full body's reaction (section 11).
  const History h = read_history(r.out / "history.csv");
  for (const std::string& column : {"top_die_force_z_N", "top_die_torque_Nm"}) {
    const double f = full.history[column].back(), p = tool_factor * h[column].back();
    char text[160];
    std::snprintf(text, sizeof text, " %s %.3g vs %.3g", column.c_str(), f, p);
    line += text;
    EXPECT_NEAR(p, f, 0.02 * std::abs(f)) << column << ": " << line;
  }
  line += "\n";
  std::printf("%s", line.c_str());
  record("verification_results.txt", line);
}

TEST(Symmetry, QuarterSectorMatchesFullRun) { compare_with_full("sector_90deg", {kSector}, 4.0, 4.0); }

TEST(Symmetry, SectorAndMirrorMatchFullRun) { compare_with_full("sector_90deg_mirror_z", {kSector, kMirror}, 8.0, 4.0); }

TEST(Symmetry, QuarterSectorWithBondFailureMatchesFullRun) {
  compare_with_full("sector_90deg_failure", {kSector}, 4.0, 4.0, kFailure);
}

TEST(Symmetry, MirrorHalfMatchesFullRun) { compare_with_full("mirror_z", {kMirror}, 2.0, 1.0); }

}  // namespace
