#!/usr/bin/env python3
"""Writes tracers.csv (one row per history row and tracer: process time, tracer, x, y, z, r, theta,
temperature, plastic strain) from the tracer columns that the friction_extrusion process writes to
history.csv (docs/processes/friction_extrusion.md). The process API gives a process no output folder,
so the paths travel in the history and this script splits them out.

usage: scripts/fe_tracers.py RUN_DIR   (writes RUN_DIR/tracers.csv)
"""
import csv
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_output import load_history  # noqa: E402


def main(run_dir: str) -> None:
    try:
        history = load_history(run_dir)
    except IndexError:
        sys.exit(f"{run_dir}/history.csv holds no rows")
    names = sorted({m.group(1) for k in history for m in [re.match(r"tracer_(P\d+)_x_m$", k)] if m},
                   key=lambda p: int(p[1:]))
    if not names:
        sys.exit(f"{run_dir}/history.csv has no tracer columns (not a friction_extrusion run?)")
    with open(f"{run_dir}/tracers.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["process_time_s", "tracer", "x_m", "y_m", "z_m", "r_m", "theta_rad", "temperature_K",
                    "plastic_strain_1"])
        rows = len(history["process_time_s"])
        for i in range(rows):
            for p in names:
                x, y, z = (history[f"tracer_{p}_{c}_m"][i] for c in "xyz")
                w.writerow([history["process_time_s"][i], p, x, y, z, math.hypot(x, y), math.atan2(y, x),
                            history[f"tracer_{p}_temperature_K"][i], history[f"tracer_{p}_plastic_strain_1"][i]])
    print(f"{run_dir}/tracers.csv: {len(names)} tracers x {rows} rows")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
