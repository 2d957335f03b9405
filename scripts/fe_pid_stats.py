#!/usr/bin/env python3
"""Force-loop statistics of friction_extrusion runs (docs/validation/friction_extrusion.md, section
"Item 1"; docs/theory.md eq. 109a): does the sampled PID loop run a period-2 cycle, and where is its
integral?

usage: scripts/fe_pid_stats.py [--from T] RUN_DIR [RUN_DIR ...]
      T: start of the window in seconds of process time (default 10)

Per run, over the history rows from T on:
- command changes that reverse the previous change (a period-2 cycle reverses every one; a stable loop
  driven by slow drift about half or fewer). Meaningful only when the history has a row within every
  PID sample (run.history_interval below the PID's sample_interval); otherwise the rows alias;
- share of rows whose command sits at the lower command limit (-0.04 mm/s in the AA7075 cases);
- the integral contribution I (median, 5th and 95th percentiles) and the share of rows within
  0.001 mm/s of the lower integral limit -0.01 mm/s;
- the die's mean plunge velocity by window of process time, from displacement differences (the
  rows' command aliases with the sampling; the displacement does not);
- summary.json's time-mean force, its deviation and the time RMSE (eq. 108a).
The PID's columns are those of the controller named `fe_pid` in the bundled cases.
"""
import json
import sys

import numpy as np

from run_output import load_history

LOWER_COMMAND_LIMIT = -0.04e-3  # m/s, the cases' command_limits[0]
LOWER_INTEGRAL_LIMIT = -0.01e-3  # m/s, the cases' integral_limits[0]
WINDOWS = [(0, 10), (10, 30), (30, 60), (60, 90), (90, 120)]  # s of process time


def stats(run, t_from):
    h = load_history(run)
    t = np.array(h["process_time_s"])
    window = t >= t_from
    command = np.array(h["fe_pid_command_m_s"])[window]
    integral = np.array(h["fe_pid_i_m_s"])[window]
    changed = np.r_[True, np.diff(command) != 0]
    steps = np.diff(command[changed])
    reversals = np.mean(np.sign(steps[1:]) != np.sign(steps[:-1])) if len(steps) > 1 else float("nan")
    print(f"{run}: {window.sum()} rows from {t_from:g} s of process")
    print(f"  command changes {len(steps)}, reversing the previous change {100 * reversals:.1f} %;"
          f" rows at the lower command limit {100 * np.mean(np.abs(command - LOWER_COMMAND_LIMIT) < 1e-12):.1f} %")
    p5, p50, p95 = np.percentile(integral, [5, 50, 95]) * 1e3
    at_clamp = np.mean(np.abs(integral - LOWER_INTEGRAL_LIMIT) < 1e-6)
    print(f"  integral I median {p50:.4f} mm/s (5-95 %: {p5:.4f} .. {p95:.4f}); within 0.001 mm/s of"
          f" -0.01 mm/s: {100 * at_clamp:.1f} %")
    z = np.array(h["die_displacement_m"])
    velocities = []
    for a, b in WINDOWS:
        i, j = np.searchsorted(t, a), np.searchsorted(t, b) - 1
        if 0 <= i < j < len(t):
            velocities.append(f"{a}-{b} s {(z[j] - z[i]) / (t[j] - t[i]) * 1e3:.4f}")
    print("  die velocity (mm/s) by window: " + ", ".join(velocities))
    try:
        with open(f"{run}/summary.json") as f:
            m = json.load(f)["metrics"]
        print(f"  time-mean force {m['steady_time_mean_force_N'] / 1e3:.2f} kN"
              f" ({m['steady_time_mean_force_deviation_pct']:+.2f} %), RMSE {m['steady_time_force_rmse_N'] / 1e3:.2f} kN")
    except (OSError, KeyError):
        print("  no finished summary.json")


def main(argv):
    t_from = 10.0
    if len(argv) > 1 and argv[0] == "--from":
        t_from, argv = float(argv[1]), argv[2:]
    if not argv:
        sys.exit(__doc__)
    for run in argv:
        stats(run, t_from)


if __name__ == "__main__":
    main(sys.argv[1:])
