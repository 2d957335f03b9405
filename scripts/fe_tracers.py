#!/usr/bin/env python3
"""Writes tracers.csv (one row per history row and tracer: process time, tracer, x, y, z, r, theta,
temperature, plastic strain) from the tracer columns that the friction_extrusion process writes to
history.csv (docs/processes/friction_extrusion.md). The process API gives a process no output folder,
so the paths travel in the history and this script splits them out.

usage: scripts/fe_tracers.py RUN_DIR   (writes RUN_DIR/tracers.csv)
"""
import csv
import math
import re
import sys


def main(run_dir: str) -> None:
    with open(f"{run_dir}/history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{run_dir}/history.csv holds no rows")
    names = sorted({m.group(1) for k in rows[0] for m in [re.match(r"tracer_(P\d+)_x_m$", k)] if m},
                   key=lambda p: int(p[1:]))
    if not names:
        sys.exit(f"{run_dir}/history.csv has no tracer columns (not a friction_extrusion run?)")
    with open(f"{run_dir}/tracers.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["process_time_s", "tracer", "x_m", "y_m", "z_m", "r_m", "theta_rad", "temperature_K",
                    "plastic_strain_1"])
        for row in rows:
            for p in names:
                x, y, z = (float(row[f"tracer_{p}_{c}_m"]) for c in "xyz")
                w.writerow([row["process_time_s"], p, x, y, z, math.hypot(x, y), math.atan2(y, x),
                            row[f"tracer_{p}_temperature_K"], row[f"tracer_{p}_plastic_strain_1"]])
    print(f"{run_dir}/tracers.csv: {len(names)} tracers x {len(rows)} rows")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
