#!/usr/bin/env python3
"""The two costs of numerics.momentum_correction (docs/verification.md 5b, theory eqs. 7, 7a, 7b) that
no test asserts, measured as the tests measure them:
  - wave bar (cases/verification/wave_bar.json, nu = 0, the settings of test_wave_bar.cpp) at 25 and
    12.5 mm: front speed between the two probes (half level of the piston velocity) against sqrt(E/rho);
  - free spinning disc (cases/verification/spinning_disc.json), one revolution: the largest relative
    change of the angular momentum about z.

usage: scripts/momentum_correction_checks.py MODE OUTDIR [--sphforge PATH]
  MODE: full, deviatoric or none. The runs go to OUTDIR/wave_MODE_25, wave_MODE_12.5, disc_MODE (--force).
  The sphforge binary: --sphforge, else $SPHFORGE, else `sphforge` on PATH (its plugins as for any run).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
from pathlib import Path

CASES = Path(__file__).resolve().parent.parent / "cases" / "verification"
E, RHO, PISTON = 10e6, 1000.0, 0.01  # test_wave_bar.cpp's material and piston speed


def run(exe, case, out, sets):
    cmd = [exe, "run", str(CASES / case), "--out", str(out), "--quiet", "--force"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode:
        sys.exit(f"{' '.join(cmd)}: exit {r.returncode}\n{r.stderr}")


def history(out):
    rows = list(csv.DictReader(open(out / "history.csv")))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def first_crossing(t, v, level):
    for k in range(1, len(v)):
        if v[k - 1] < level <= v[k]:
            return t[k - 1] + (t[k] - t[k - 1]) * (level - v[k - 1]) / (v[k] - v[k - 1])
    return float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", choices=["full", "deviatoric", "none"])
    ap.add_argument("outdir", type=Path)
    ap.add_argument("--sphforge", default=os.environ.get("SPHFORGE", "sphforge"))
    a = ap.parse_args()
    mode_set = "numerics.momentum_correction=" + a.mode
    exact = (E / RHO) ** 0.5
    for dx in ("25", "12.5"):
        out = a.outdir / f"wave_{a.mode}_{dx}"
        run(a.sphforge, "wave_bar.json", out,
            [f"process.particle_spacing={dx} mm", "material.youngs_modulus=10 MPa", "material.density=1000 kg/m^3",
             "material.poisson_ratio=0", mode_set])
        h, m = history(out), json.load(open(out / "summary.json"))["metrics"]
        t1 = first_crossing(h["time_s"], h["near_velocity_x_m_s"], 0.5 * PISTON)
        t2 = first_crossing(h["time_s"], h["far_velocity_x_m_s"], 0.5 * PISTON)
        speed = (m["far_velocity_x_x0_m"] - m["near_velocity_x_x0_m"]) / (t2 - t1)
        print(f"wave bar, {a.mode}, dx {dx} mm: {speed:.4f} m/s, error {100 * (speed / exact - 1):+.3f} %")
    out = a.outdir / f"disc_{a.mode}"
    run(a.sphforge, "spinning_disc.json", out, [mode_set])
    hz = history(out)["angular_momentum_z_kg_m2_s"]
    print(f"spinning disc, {a.mode}: angular momentum max relative change "
          f"{max(abs(x - hz[0]) for x in hz) / abs(hz[0]):.3e}")


if __name__ == "__main__":
    main()
