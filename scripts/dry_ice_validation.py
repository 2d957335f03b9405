#!/usr/bin/env python3
"""Dry-ice validation (docs/validation/dry_ice.md): runs the 13 dry_ice_<die>[SUFFIX] cases (or only
reads finished runs with --no-run), takes F_L = the largest history ram_force_N of each run, and
compares the 7 published dies (CS, WK) with the experimental medians of
cases/ram_extrusion/reference/dry_ice_force_public.csv. Prints a Markdown table and the mean absolute
relative error; exit code 1 when it exceeds --target (the issue's 10 %).

  python3 scripts/dry_ice_validation.py --sphforge build/nocuda/bin/sphforge --out DIR [--suffix _quick]
          [--set key=value ...] [--no-run] [--target 0.10]
"""
import argparse
import csv
import json
import os
import subprocess
import sys

from run_output import load_history

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIES = ["CS50", "CS75", "CS100", "CS150", "WK20", "WK45", "WK70", "WP20", "WP45", "WP70",
        "WKWP70-25", "WKWP70-50", "WKWP70-75"]


def peak_force(run_dir):
    history = load_history(run_dir)
    force = history["ram_force_N"]
    k = max(range(len(force)), key=force.__getitem__)  # the first row at the peak
    return force[k], history["ram_displacement_m"][k]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sphforge", default=os.path.join(ROOT, "build", "nocuda", "bin", "sphforge"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--suffix", default="")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--no-run", action="store_true")
    ap.add_argument("--target", type=float, default=0.10)
    a = ap.parse_args()
    ref = {}
    with open(os.path.join(ROOT, "cases", "ram_extrusion", "reference", "dry_ice_force_public.csv"), newline="") as f:
        for r in csv.DictReader(f):
            ref[r["die"]] = r
    print("| die | F_L sim (N) | at s (mm) | exp. median (N) | error | paper SPH error | wall (s) |")
    print("|---|---|---|---|---|---|---|")
    errors = []
    for die in DIES:
        run = os.path.join(a.out, die)
        if not a.no_run:
            case = os.path.join(ROOT, "cases", "ram_extrusion", "dry_ice", f"dry_ice_{die}{a.suffix}.json")
            cmd = [a.sphforge, "run", case, "--out", run, "--quiet", "--force"]
            for s in a.set:
                cmd += ["--set", s]
            subprocess.run(cmd, check=True)
        if not os.path.exists(os.path.join(run, "summary.json")):
            print(f"| {die} | not run | | | | | |")
            continue
        F, s = peak_force(run)
        wall = json.load(open(os.path.join(run, "summary.json"))).get("wall_time_s", float("nan"))
        if die in ref:
            exp = float(ref[die]["F_L_exp_median_N"])
            paper = float(ref[die]["F_L_paper_sph_N"])
            err = (F - exp) / exp
            errors.append(abs(err))
            print(f"| {die} | {F:.0f} | {1e3 * s:.1f} | {exp:.0f} | {100 * err:+.1f} % | {100 * (paper - exp) / exp:+.1f} % | {wall:.0f} |")
        else:
            print(f"| {die} | {F:.0f} | {1e3 * s:.1f} | held out | prediction | | {wall:.0f} |")
    if not errors:
        return 1
    mae = sum(errors) / len(errors)
    print(f"\nmean absolute error over the {len(errors)} published dies: {100 * mae:.1f} % (target {100 * a.target:.0f} %)")
    return 0 if mae <= a.target and len(errors) == 7 else 1


if __name__ == "__main__":
    sys.exit(main())
