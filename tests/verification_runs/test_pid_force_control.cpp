// Verification 12 (docs/verification.md section 12): PID force control in an SPH run
// (cases/verification/pid_force_block.json, 1000 particles, ~2,900 steps, ~5 s on one thread).
//
// A punch plane on an elastic block (E = 1 MPa, 10 mm cube, frictionless table and punch) is driven
// by the `pid` controller on the punch force, target 1 N, Kp = -0.05 m/s/N (closed-loop time constant
// 1/(k |Kp|) = 2 ms with k = E A / L = 1e4 N/m). After 15 ms (7.5 time constants):
// - the force: mean |F - 1 N| < 1 % of the target (the issue's tolerance; the loop removes any static
//   error of the plant, which integrates the commanded velocity);
// - the block's shortening between its bottom and top particle layers against F (L - dx) / (E A).
//   The issue asks 3 %. Measured: -8.6 % at dx = 1 mm (this test) and -4.7 % at 0.5 mm (by hand,
//   8,000 particles, 129 s): the SPH block is stiffer, by a boundary layer at the loaded faces (the
//   first particle layer carries 0.61 of the mean stress, the strain between the first two layers is
//   0.64 of E^-1 sigma; the interior strain is within 3.5 %), converging with about first order. The
//   3 % is NOT met by this cube; the bound below, 10 %, is a regression bound around the measured -8.6 %,
//   not the issue's criterion. The layer is a fixed number of particle layers, so its relative size
//   falls as dx/L: the slender block (L/dx = 40) of test_pid_force_slender.cpp checks the 3 %
//   (-2.8 % measured).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "pid_block.hpp"

namespace {

using namespace sphforge_verification;

TEST(PidForceControl, PunchSettlesAtTheTargetForceOnAnElasticBlock) {
  const RunResult run = run_case("pid_force_block.json", "pid_force_block", {});
  ASSERT_EQ(run.code, 0) << run.err;
  const PidBlockResult r = analyse_pid_block(run.out, "pid_force_block", 1.0, 1e6, 1e-4, 10e-3, 1e-3, 15e-3);
  ASSERT_GT(r.rows, 100);
  std::printf("%s\n", r.line.c_str());
  record("verification_results.txt", r.line + "\n");
  EXPECT_LT(r.mean_abs_force_error, 0.01);           // the issue's 1 %
  EXPECT_LT(std::abs(r.shortening_error), 0.10);     // regression bound (see the header): the 3 % is checked on
                                                     // the slender block (test_pid_force_slender.cpp)
  const History h = read_history(run.out / "history.csv");
  EXPECT_GT(std::abs(h["force_command_m_s"][1]), 0.0);  // the punch was driven

  // Energy ledger (theory eq. 27) of a block held between two walls: at rest, the punch's work equals
  // kinetic + internal energy plus what the penalty springs of both walls hold, F g / 2 each (N equal
  // springs of stiffness k carrying F: N k g^2 / 2 = F g / 2, g the mean penetration). Bound 1 %: the
  // ledger leaves out the contact damping's dissipation and the spread of g about its mean, both
  // small in this slow, frictionless loading (measured 0.07 %). With the step-centred velocity built
  // from the internal acceleration alone (the code before 2026-11-30), the internal energy came out
  // at -2.9e-3 J against the 4.1e-5 J stored: a 6,000 % error that grows with every step a wall holds load.
  const std::size_t last = h.rows - 1;
  const double work = h["tool_work_J"][last], internal = h["internal_energy_J"][last],
               kinetic = h["kinetic_energy_J"][last];
  double springs = 0.0;
  for (const char* wall : {"punch", "table"})
    springs += 0.5 * std::abs(h[std::string(wall) + "_force_z_N"][last]) *
               h[std::string(wall) + "_penetration_mean_m"][last];
  const double closure = (work - kinetic - internal - springs) / work;
  std::printf("energy ledger: work %.6g J, internal %.6g J, kinetic %.3g J, wall springs %.4g J, closure %.4f %%\n", work,
              internal, kinetic, springs, 100.0 * closure);
  EXPECT_GT(internal, 0.0);
  EXPECT_LT(std::abs(closure), 0.01);
}

}  // namespace

namespace {

TEST(PidForceControl, PhaseEndsWhenAProbeSignalCrossesItsThreshold) {
  // The generic process publishes every probe and every tool position as measured signals: a phase
  // that ends when the block's top has moved 0.03 mm down switches at the first step past it.
  const RunResult run = run_case(
      "pid_force_block.json", "pid_force_block_phases",
      {R"(phases=[{"name":"press","end":{"signal":"top_displacement_z","below":"-0.03 mm"}},)"
       R"({"name":"hold","end":{"signal":"punch_position","below":"-1 m"}}])",
       "run.end_time=8 ms"});
  ASSERT_EQ(run.code, 0) << run.err;
  const json summary = read_summary(run.out);
  ASSERT_TRUE(summary.contains("phases")) << summary.dump(2);
  const double switched = summary["phases"][0]["end_s"].get<double>();
  EXPECT_TRUE(summary["phases"][1]["end_s"].is_null());  // the punch never reaches -1 m
  const History h = read_history(run.out / "history.csv");
  const auto& t = h["time_s"];
  const auto& top = h["top_displacement_z_m"];
  const auto& phase = h["phase_1"];
  for (std::size_t k = 1; k < t.size(); ++k) {
    if (t[k] < switched) {
      EXPECT_EQ(phase[k], 1.0) << t[k];
      EXPECT_GE(top[k], -0.03e-3) << t[k];  // still above the threshold: the phase has not ended
    } else if (t[k] > switched) {
      EXPECT_EQ(phase[k], 2.0) << t[k];
    }
  }
}

}  // namespace
