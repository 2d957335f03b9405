// Verification 15 (docs/verification.md section 15): material separation by bond failure
// (docs/theory.md eqs. 110-115, docs/failure.md), without deleting particles.
//
// Notched bar (cases/verification/notched_bar_failure.json, 528 particles, a one-layer double-edge
// notch at mid-length): pulled at both ends for 160 us, run three times: without failure, with
// failure_plastic_strain 0.1 and with 0.2. The axial force is the mean sigma_xx of the two particle
// layers of the left shank at 4-6 mm (by initial position) times the shank section, from the frames
// (every 5 us).
//  (a) until the first particle fails, the force history with failure is the one without it, and the
//      first particle fails in the frame where the run without failure first shows eps_f;
//  (b) after, the bar separates: in the last 50 us the shank force swings through zero (a released
//      half rings freely; the run without failure stays above half its peak) and the grips end in two
//      pieces with no particle pair between them closer than 1.5 dx (the lattice spacing is 1 dx);
//  (c) with 0.2 the force drops later than with 0.1, and in each run only after the first failure;
//  particle count and total mass are unchanged (nothing deleted, eq. 115).
// Why not the paper's 0.4: at this resolution the run without failure itself starts to tear at the
// notch once its plastic strain there passes ~0.4 (force down from 7.0 kN at 110 us to 4.2 kN at
// 180 us), so a failure strain must stay well below that for the bond rule, not the discretisation,
// to decide where and when the bar separates (docs/verification.md section 15).
// Compressed block (cases/verification/compressed_block_failure.json, 1,000 particles): a block
// whose particles all fail early (eps_f = 0.1) under uniaxial compression to 40 % reduction keeps the
// punch force of the run without failure (broken bonds transmit compression, eq. 112).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

constexpr double kShankArea = 8e-3 * 3e-3;  // m^2, the bar's 8 x 3 mm section outside the notch
constexpr double kDx = 1e-3;                 // m, particle spacing of the case
constexpr double kFrameInterval = 5e-6;      // s, the case's output_interval

struct BarRun {
  RunResult run;
  std::vector<double> t, force;           // per frame: s, N
  std::vector<double> max_strain;         // largest plastic strain per frame
  std::vector<std::size_t> failed;        // failed particles per frame (0 without the field)
  double min_failed_strain = INFINITY;    // smallest plastic strain of a failed particle, all frames
  std::vector<std::size_t> count;         // particles per frame
  std::vector<double> mass;               // total mass per frame, kg
  Frame last;
};

BarRun run_bar(const std::string& name, double failure_strain) {
  BarRun b;
  char set[80];
  std::snprintf(set, sizeof set, "material.failure_plastic_strain=%.17g", failure_strain);
  b.run = run_case("notched_bar_failure.json", name, {set});
  if (b.run.code != 0) return b;
  const std::vector<fs::path> files = frames(b.run.out);
  std::map<long long, double> x0;  // initial x by particle id
  for (std::size_t k = 0; k < files.size(); ++k) {
    Frame f = read_frame(files[k]);
    const std::vector<double>& id = f.arrays.at("id");
    const std::vector<double>& x = f.arrays.at("position");
    const std::vector<double>& S = f.arrays.at("deviatoric_stress");
    const std::vector<double>& p = f.arrays.at("pressure");
    const std::vector<double>& eps = f.arrays.at("plastic_strain");
    const std::vector<double>& m = f.arrays.at("mass");
    const std::vector<double>* flags = f.arrays.count("failed") ? &f.arrays.at("failed") : nullptr;
    double sxx = 0.0, max_eps = 0.0;
    std::size_t in_slab = 0, failed = 0;
    for (std::size_t i = 0; i < f.count; ++i) {
      const long long key = std::llround(id[i]);
      if (k == 0) x0[key] = x[3 * i];
      const double xi0 = x0.at(key);
      if (xi0 > 4e-3 && xi0 < 6e-3) sxx += S[6 * i] - p[i], ++in_slab;  // VTK order xx yy zz xy yz xz
      max_eps = std::max(max_eps, eps[i]);
      if (flags && (*flags)[i] > 0.5) {
        ++failed;
        b.min_failed_strain = std::min(b.min_failed_strain, eps[i]);
      }
    }
    b.t.push_back(static_cast<double>(k) * kFrameInterval);
    b.force.push_back(in_slab ? kShankArea * sxx / static_cast<double>(in_slab) : std::nan(""));
    b.max_strain.push_back(max_eps);
    b.failed.push_back(failed);
    b.count.push_back(f.count);
    b.mass.push_back(std::accumulate(m.begin(), m.end(), 0.0));
    if (k + 1 == files.size()) b.last = std::move(f);
  }
  return b;
}

double peak(const std::vector<double>& f) { return *std::max_element(f.begin(), f.end()); }

/// Index of the first frame with a failed particle (size() if none).
std::size_t first_failure(const BarRun& b) {
  return static_cast<std::size_t>(std::find_if(b.failed.begin(), b.failed.end(), [](std::size_t n) { return n > 0; }) -
                                  b.failed.begin());
}

/// Index of the first frame at which the largest plastic strain reached `eps` (size() if never).
std::size_t strain_frame(const BarRun& b, double eps) {
  return static_cast<std::size_t>(
      std::find_if(b.max_strain.begin(), b.max_strain.end(), [&](double e) { return e >= eps; }) - b.max_strain.begin());
}

/// First time the force falls below `fraction` of `reference` from frame `from` on (NaN if never).
double drop_time(const BarRun& b, std::size_t from, double fraction, double reference) {
  for (std::size_t k = from; k < b.force.size(); ++k)
    if (b.force[k] < fraction * reference) return b.t[k];
  return std::nan("");
}

/// Smallest force over the frames at t >= t_from.
double min_force_after(const BarRun& b, double t_from) {
  double lowest = INFINITY;
  for (std::size_t k = 0; k < b.t.size(); ++k)
    if (b.t[k] >= t_from - 1e-12) lowest = std::min(lowest, b.force[k]);
  return lowest;
}

/// Pieces of a frame: particles linked when closer than `link`. Whether the particles with the
/// smallest and the largest x (the grips' ends) are in different pieces, and the smallest distance
/// between those two pieces.
struct Pieces {
  bool separate = false;
  double gap = 0.0;
  std::size_t components = 0;
};
Pieces pieces(const Frame& f, double link) {
  const std::vector<double>& x = f.arrays.at("position");
  const std::size_t n = f.count;
  const auto dist2 = [&](std::size_t i, std::size_t j) {
    const double d0 = x[3 * i] - x[3 * j], d1 = x[3 * i + 1] - x[3 * j + 1], d2 = x[3 * i + 2] - x[3 * j + 2];
    return d0 * d0 + d1 * d1 + d2 * d2;
  };
  std::vector<std::size_t> label(n, SIZE_MAX);
  std::size_t next = 0;
  for (std::size_t s = 0; s < n; ++s) {
    if (label[s] != SIZE_MAX) continue;
    std::vector<std::size_t> stack = {s};
    label[s] = next;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      for (std::size_t j = 0; j < n; ++j)
        if (label[j] == SIZE_MAX && dist2(i, j) < link * link) label[j] = next, stack.push_back(j);
    }
    ++next;
  }
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (x[3 * i] < x[3 * lo]) lo = i;
    if (x[3 * i] > x[3 * hi]) hi = i;
  }
  Pieces p;
  p.components = next;
  p.separate = label[lo] != label[hi];
  if (p.separate) {
    double best = INFINITY;
    for (std::size_t i = 0; i < n; ++i)
      if (label[i] == label[lo])
        for (std::size_t j = 0; j < n; ++j)
          if (label[j] == label[hi]) best = std::min(best, dist2(i, j));
    p.gap = std::sqrt(best);
  }
  return p;
}

TEST(BondFailure, NotchedBarSeparatesAtTheStatedStrain) {
  const BarRun none = run_bar("failure_bar_none", 0.0);
  ASSERT_EQ(none.run.code, 0) << none.run.err;
  const BarRun low = run_bar("failure_bar_01", 0.1);
  ASSERT_EQ(low.run.code, 0) << low.run.err;
  const BarRun high = run_bar("failure_bar_02", 0.2);
  ASSERT_EQ(high.run.code, 0) << high.run.err;
  ASSERT_EQ(none.t.size(), low.t.size());
  ASSERT_EQ(none.t.size(), high.t.size());
  ASSERT_GE(none.t.size(), 30u);  // 160 us in frames of 5 us

  const double f_peak = peak(none.force);
  const std::size_t k_fail01 = first_failure(low), k_fail02 = first_failure(high);
  const std::size_t k_eps01 = strain_frame(none, 0.1), k_eps02 = strain_frame(none, 0.2);
  ASSERT_LT(k_fail01, low.t.size());
  ASSERT_LT(k_fail02, high.t.size());
  // Largest force difference to the run without failure in the frames before the first failure.
  double diff01 = 0.0, diff02 = 0.0;
  for (std::size_t k = 0; k < k_fail01; ++k) diff01 = std::max(diff01, std::abs(low.force[k] - none.force[k]));
  for (std::size_t k = 0; k < k_fail02; ++k) diff02 = std::max(diff02, std::abs(high.force[k] - none.force[k]));
  // Drop: below 25 % of the peak force. The bar without failure stays above 75 % of its peak after it
  // within the run (lowest 76 %), so 25 % is reached only by a bar that has come apart.
  const double t_drop01 = drop_time(low, k_fail01, 0.25, f_peak), t_drop02 = drop_time(high, k_fail02, 0.25, f_peak);
  const std::size_t k_peak =
      static_cast<std::size_t>(std::max_element(none.force.begin(), none.force.end()) - none.force.begin());
  const double t_drop_none = drop_time(none, k_peak, 0.25, f_peak);
  const double t_tail = none.t.back() - 50e-6;
  const double tail_none = min_force_after(none, t_tail), tail01 = min_force_after(low, t_tail),
               tail02 = min_force_after(high, t_tail);
  const double link = 1.5 * kDx;
  const Pieces p_none = pieces(none.last, link), p01 = pieces(low.last, link), p02 = pieces(high.last, link);
  char line[1200];
  std::snprintf(line, sizeof line,
                "notched bar: %zu particles; peak force %.2f kN (no failure). Max plastic strain of the run without "
                "failure reaches 0.1 at %.0f us, 0.2 at %.0f us. eps_f 0.1: first failure %.0f us (smallest failed "
                "strain %.4f), force diff before %.3g N, force < 25%% of peak at %.0f us, least force last 50 us "
                "%.3f kN, pieces %zu separate %d gap %.2f mm. eps_f 0.2: first failure %.0f us (smallest failed "
                "strain %.4f), diff %.3g N, drop at %.0f us, least last 50 us %.3f kN, pieces %zu separate %d gap "
                "%.2f mm. Without failure: drop %.0f us, least last 50 us %.3f kN, separate %d. Count %zu -> %zu, "
                "mass %.9g -> %.9g kg\n",
                low.count.front(), f_peak * 1e-3, none.t[std::min(k_eps01, none.t.size() - 1)] * 1e6,
                none.t[std::min(k_eps02, none.t.size() - 1)] * 1e6, low.t[k_fail01] * 1e6, low.min_failed_strain,
                diff01, t_drop01 * 1e6, tail01 * 1e-3, p01.components, p01.separate, p01.gap * 1e3,
                high.t[k_fail02] * 1e6, high.min_failed_strain, diff02, t_drop02 * 1e6, tail02 * 1e-3,
                p02.components, p02.separate, p02.gap * 1e3, t_drop_none * 1e6, tail_none * 1e-3, p_none.separate,
                low.count.front(), low.count.back(), low.mass.front(), low.mass.back());
  std::printf("%s", line);
  record("verification_results.txt", line);

  // (a) Identical force history until the first particle fails: before it every flag is 0 and the
  // rule multiplies each pair by exactly 1, so the only possible difference is the round-off of the
  // other loop instance (FMA contraction may differ): 1e-9 of the peak force is far above that
  // round-off and far below any physical change.
  EXPECT_GE(k_fail01, 5u) << line;  // something to compare
  EXPECT_LE(diff01, 1e-9 * f_peak) << line;
  EXPECT_LE(diff02, 1e-9 * f_peak) << line;
  // At the stated strain, not before (eq. 110): the first particle fails in the frame where the run
  // without failure first shows that plastic strain (the two runs are the same until then), and no
  // failed particle has less.
  EXPECT_EQ(k_fail01, k_eps01) << line;
  EXPECT_EQ(k_fail02, k_eps02) << line;
  EXPECT_GE(low.min_failed_strain, 0.1) << line;
  EXPECT_GE(high.min_failed_strain, 0.2) << line;

  // The control: without failure the bar still carries load at the end (else (b) proves nothing):
  // one piece, and the shank force never below half the peak in the last 50 us.
  EXPECT_FALSE(p_none.separate) << line;
  EXPECT_GT(tail_none, 0.5 * f_peak) << line;

  // (b) Separation: in the last 50 us the shank force changes sign. A bar still joined at the notch
  // and pulled at both ends keeps its shank in tension (the run without failure: above half the
  // peak); a released half rings freely about zero (+-2 kN, a period of ~20 us, so 50 us holds two
  // compressive swings). And the grips' pieces are apart: no pair closer than 1.5 dx.
  EXPECT_LT(tail01, 0.0) << line;
  EXPECT_LT(tail02, 0.0) << line;
  EXPECT_TRUE(p01.separate) << line;
  EXPECT_TRUE(p02.separate) << line;
  EXPECT_GT(p01.gap, link) << line;
  EXPECT_GT(p02.gap, link) << line;

  // (c) The force drops after the first failure (drop_time searches from there, so it must exist) and
  // later with the higher failure strain.
  EXPECT_FALSE(std::isnan(t_drop01)) << line;
  EXPECT_FALSE(std::isnan(t_drop02)) << line;
  EXPECT_GT(t_drop02, t_drop01) << line;

  // Nothing deleted (eq. 115): every frame has the particles and the mass of the first (summed in
  // the same order: exact).
  for (const BarRun* b : {&none, &low, &high})
    for (std::size_t k = 0; k < b->count.size(); ++k) {
      EXPECT_EQ(b->count[k], b->count.front()) << line;
      EXPECT_EQ(b->mass[k], b->mass.front()) << line;
    }
}

TEST(BondFailure, CompressedFailedBlockKeepsItsStrength) {
  const RunResult none = run_case("compressed_block_failure.json", "failure_block_none",
                                  {"material.failure_plastic_strain=0"});
  ASSERT_EQ(none.code, 0) << none.err;
  const RunResult with = run_case("compressed_block_failure.json", "failure_block_01", {});
  ASSERT_EQ(with.code, 0) << with.err;
  const History h0 = read_history(none.out / "history.csv"), h1 = read_history(with.out / "history.csv");
  ASSERT_EQ(h0.rows, h1.rows);
  const std::vector<double>& f0 = h0["punch_force_z_N"];
  const std::vector<double>& f1 = h1["punch_force_z_N"];
  // Compare over the last third of the compression (strain 27-40 %, every particle failed by then).
  const std::size_t from = 2 * h0.rows / 3;
  double worst = 0.0, mean0 = 0.0, mean1 = 0.0;
  for (std::size_t k = from; k < h0.rows; ++k) {
    worst = std::max(worst, std::abs(f1[k] - f0[k]) / std::abs(f0[k]));
    mean0 += f0[k], mean1 += f1[k];
  }
  mean0 /= static_cast<double>(h0.rows - from);
  mean1 /= static_cast<double>(h0.rows - from);
  const std::vector<fs::path> files = frames(with.out);
  const Frame last = read_frame(files.back());
  std::size_t failed = 0;
  for (double f : last.arrays.at("failed")) failed += f > 0.5 ? 1 : 0;
  char line[400];
  std::snprintf(line, sizeof line,
                "compressed block: %zu of %zu particles failed; punch force over the last third: mean %.2f kN "
                "without failure, %.2f kN with (ratio %.4f), largest pointwise difference %.2f %%\n",
                failed, last.count, mean0 * 1e-3, mean1 * 1e-3, mean1 / mean0, worst * 100.0);
  std::printf("%s", line);
  record("verification_results.txt", line);
  // The test is meaningful only if the material has failed nearly everywhere.
  EXPECT_GT(failed, 9 * last.count / 10) << line;
  EXPECT_GT(mean0, 0.0) << line;  // the block pushes the punch up (+z)
  // Load-carrying kept: the mean force within 5 % of the run without failure. Why 5 %: the failed
  // block still loses the pairs whose normal stress turns tensile (lateral pairs carry ~0 normal stress
  // in uniaxial compression, so noise decides their sign), which changes the flow a little; losing
  // the compressed pairs would remove the load path itself, far more than 5 %.
  EXPECT_NEAR(mean1 / mean0, 1.0, 0.05) << line;
}

}  // namespace
