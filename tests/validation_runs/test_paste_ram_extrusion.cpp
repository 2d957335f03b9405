// Validation (label `validation`, not run in CI: each full run takes minutes on one thread) of the
// paste ram extrusion cases in cases/ram_extrusion/ against the analytic targets of issue 7
// (reference numbers: cases/ram_extrusion/reference/paste_ram_extrusion.md and the *_reference.csv
// files there). The tolerances are the issue's accuracy targets, not tuned bounds;
// docs/validation/ram_extrusion.md reports the measured numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

// The ram extrusion cases, relative to kCases (cases/verification).
const std::string kDir = "../ram_extrusion/";
constexpr double kSigmaY = 0.38e6, kD0 = 25e-3, kD = 3e-3;
constexpr double kTau0 = 1.8e4, kBeta = 5.4e5, kN = 0.58;  // the paper's Navier-slip fit

double tau_w(double v) { return kTau0 + kBeta * std::pow(v, kN); }  // eq. (18g)

double steady_pressure(const RunResult& r, const char* metric = "steady_extrusion_pressure_Pa") {
  EXPECT_EQ(r.code, 0) << r.err;
  const json s = read_summary(r.out);
  // The paste cases end at their stroke (process_finished); the quick orifice case at its end time.
  EXPECT_TRUE(s["status"] == "process_finished" || s["status"] == "completed") << s["status"];
  const json& m = s["metrics"][metric];
  return m.is_number() ? m.get<double>() : std::nan("");
}

// 1. Smooth walls, square-entry orifice: the die-entry pressure P_1 within 5 % of Horrobin-Nedderman
//    (eq. 76) and above the ideal work 2 sigma_y ln(D0/D). P_1 is measured as the paper defines P_ex:
//    the axial stress averaged over the barrel section 1.5 R0 above the die face (eq. 73,
//    `steady_section_pressure_Pa`); with a frictionless barrel the ram pressure would be the same, and it
//    is recorded beside it. Run on the paper's 40 mm billet, so that the section lies 21 mm below the
//    ram face and not inside its kernel support (with the bundled 22.5 mm billet the section is biased
//    low by about 4 %), at dx = 0.5 mm (six particles across the orifice): at 0.75 mm the section is
//    +5.0 % and the ram +7.1 %; the same run at 0.5 mm (via a restart, 2026-12-04) gave +3.06 % and
//    +3.7 % (docs/validation/ram_extrusion.md 1a).
//    The case's 1.5 mm stroke and window 1.0-1.5 mm: at its 1e6 kg/m^3 a 0.5-0.8 mm window is still in
//    the start-up transient. 142,750 steps of 39,200 particles: about 3 h on one thread, 5,963 s on two
//    (SPHFORGE_TEST_THREADS=2, 2026-12-04: passed, section +3.04 %, ram +3.72 %).
TEST(PasteRamExtrusionValidation, SmoothOrificeHorrobinNedderman) {
  const RunResult r = run_case(kDir + "paste_orifice.json", "paste_orifice_smooth",
                               {R"(contact.tool_laws.barrel={"plugin":"coulomb","friction_coefficient":0.0})",
                                "process.billet_height=40 mm", "process.particle_spacing=0.5 mm"});
  const double p_ex = steady_pressure(r);
  const double p_section = steady_pressure(r, "steady_section_pressure_Pa");
  const double p1 = kSigmaY * (1.92 * std::log(kD0 / kD) + 1.08);
  const double ideal = 2.0 * kSigmaY * std::log(kD0 / kD);
  char text[300];
  std::snprintf(text, sizeof text,
                "paste orifice, smooth walls, 40 mm billet, dx 0.5 mm: section P %.4g Pa, P_1 (H-N) %.4g Pa: "
                "%+.2f %%; ram P_ex %.4g Pa: %+.2f %%; ideal %.4g Pa\n",
                p_section, p1, 100.0 * (p_section / p1 - 1.0), p_ex, 100.0 * (p_ex / p1 - 1.0), ideal);
  record("validation_results.txt", text);
  EXPECT_NEAR(p_section, p1, 0.05 * p1) << text;  // the issue's 5 % target
  EXPECT_GT(p_section, ideal) << text;            // a lower bound: no tolerance
  EXPECT_GT(p_ex, ideal) << text;
}

// 2. Navier-slip lands: the slope of P_ex against L/D (least squares through L/D = 0, 10/3, 28/3)
//    within 3 % of 4 tau_w(V_ex) (eq. 77). At the case's 1e6 kg/m^3 the 28 mm land extrudes only from
//    u = 1.3 mm, so that die runs a 2.5 mm stroke with the window 1.8-2.5 mm, where its P_ex levels
//    off; the others keep the case's 1.5 mm and 1.0-1.5 mm. L/D = 52/3 is left out: it fills later
//    still (docs/validation/ram_extrusion.md, 2a/3a).
TEST(PasteRamExtrusionValidation, NavierLandSlope) {
  const double ld[] = {0.0, 10.0 / 3.0, 28.0 / 3.0};
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  std::string rows;
  for (double x : ld) {
    char set[80];
    std::snprintf(set, sizeof set, "process.land_length=%.6g mm", x * kD * 1e3);
    char name[80];
    std::snprintf(name, sizeof name, "paste_land_LD%.2f", x);
    std::vector<std::string> sets = {set};
    const bool fills_late = x > 9.0;  // the 28 mm land (L/D = 28/3)
    if (fills_late)
      sets.insert(sets.end(), {"process.stroke=2.5 mm", "process.steady_window_start=1.8 mm",
                               "process.steady_window_end=2.5 mm", "run.end_time=2.6 s", "numerics.domain_margin=0.3 m"});
    const double p = steady_pressure(run_case(kDir + "paste_land.json", name, sets));
    char row[120];
    std::snprintf(row, sizeof row, "  L/D %.3f: P_ex %.4g Pa\n", x, p);
    rows += row;
    sx += x, sy += p, sxx += x * x, sxy += x * p;
  }
  const double n = 3.0, slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  const double v_ex = 1e-3 * (kD0 / kD) * (kD0 / kD), target = 4.0 * tau_w(v_ex);
  char text[200];
  std::snprintf(text, sizeof text, "paste lands: slope dP_ex/d(L/D) %.4g Pa, 4 tau_w(V_ex) %.4g Pa: %+.2f %%\n", slope,
                target, 100.0 * (slope / target - 1.0));
  record("validation_results.txt", rows + text);
  EXPECT_NEAR(slope, target, 0.03 * target) << rows << text;  // the issue's 3 % target
}

// 3. Benbow-Bridgwater (square entry, eq. 78) at the paper's ram speeds, L/D = 10/3: a table (no
//    target in the issue; the test fails only if a run fails).
TEST(PasteRamExtrusionValidation, BenbowBridgwaterSpeeds) {
  std::string rows = "paste land L/D = 10/3 against Benbow-Bridgwater (sigma_0 = 0.6 MPa, alpha = 0):\n";
  for (double v : {0.5, 1.0, 2.0, 3.0, 5.0}) {
    char set[80];
    std::snprintf(set, sizeof set, "controllers.0.value=%g mm/s", v);
    char name[80];
    std::snprintf(name, sizeof name, "paste_land_V%g", v);
    // Same ram displacements at every speed: the end time scales with 1/V. The density scales as
    // 1/V^2 from the case's 1e6 kg/m^3 at 1 mm/s, so that the inertia (rho V_ex^2) and the number of
    // steps are the same at every speed (the paper lowers its density with the speed too).
    char end[80], density[80];
    std::snprintf(end, sizeof end, "run.end_time=%g s", 1.6 / v);  // the case's 1.5 mm stroke, with margin
    std::snprintf(density, sizeof density, "material.density=%g kg/m^3", 1e6 / (v * v));
    const double p = steady_pressure(run_case(kDir + "paste_land.json", name, {set, end, density}));
    const double v_ex = 1e-3 * v * (kD0 / kD) * (kD0 / kD);
    const double bb = 2.0 * 0.6e6 * std::log(kD0 / kD) + 4.0 * (10.0 / 3.0) * tau_w(v_ex);
    char row[160];
    std::snprintf(row, sizeof row, "  V_ram %g mm/s: P_ex %.4g Pa, B-B %.4g Pa, %+.1f %%\n", v, p, bb, 100.0 * (p / bb - 1.0));
    rows += row;
    EXPECT_TRUE(std::isfinite(p)) << row;
  }
  record("validation_results.txt", rows);
  std::printf("%s", rows.c_str());
}

// Symmetry: the quick orifice case (cubic lattice, which the 90 deg rotation maps onto itself:
// the sector holds exactly a quarter of the full run's particles, eq. 30) in full and as a 90 deg
// sector. The two runs compute the same particles with the same operations; only the order of the
// sums over ghosts differs, so the steady P_ex must agree to round-off, amplified over ~4000 steps
// of plastic flow: 1e-6 relative. The speed-up is reported, not tested (a wall time, not a benchmark).
TEST(PasteRamExtrusionValidation, SectorMatchesFullRun) {
  const RunResult full = run_case(kDir + "paste_orifice_quick.json", "paste_orifice_quick_full", {});
  const RunResult sector =
      run_case(kDir + "paste_orifice_quick.json", "paste_orifice_quick_sector",
               {R"(numerics.symmetry={"sector":{"angle":"90 deg"}})", "process.sector_count=4"});
  const double p_full = steady_pressure(full), p_sector = steady_pressure(sector);
  const json sf = read_summary(full.out), ss = read_summary(sector.out);
  char text[300];
  std::snprintf(text, sizeof text,
                "paste orifice quick, cubic lattice: full P_ex %.10g Pa (%d particles), sector %.10g Pa (%d): %.2e "
                "relative; wall %.1f s vs %.1f s (speed-up %.2f)\n",
                p_full, sf["particles"].get<int>(), p_sector, ss["particles"].get<int>(), p_sector / p_full - 1.0,
                sf["wall_time_s"].get<double>(), ss["wall_time_s"].get<double>(),
                sf["wall_time_s"].get<double>() / ss["wall_time_s"].get<double>());
  record("validation_results.txt", text);
  EXPECT_EQ(4 * ss["particles"].get<int>(), sf["particles"].get<int>()) << text;
  EXPECT_NEAR(p_sector, p_full, 1e-6 * p_full) << text;
}

}  // namespace
