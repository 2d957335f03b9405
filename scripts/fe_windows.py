#!/usr/bin/env python3
"""Window means of a friction_extrusion run's history (docs/validation/friction_extrusion.md): for each
window of process time, the extrusion force (mean, RMSE against the target), the die's plunge velocity
from the displacement difference (history rows alias with the PID's sampling, so the rows' command is
not averaged), interface and die thermocouple temperatures, plastic and friction heat rates (process
plugin, eq. 104), die contacts and their sticking fraction, the largest kinetic/internal energy ratio,
and the tracers' plastic strain at the window's end.

usage: scripts/fe_windows.py RUN [--windows 0,10,30,60,90,120] [--target 300e3]
A run still writing is read up to its last complete row; the last window ends there.
"""
import argparse
import math

from run_output import load_history


def window_rows(h, t0, t1):
    t = h["process_time_s"]
    return [i for i, ti in enumerate(t) if t0 <= ti <= t1]


def mean(values):
    values = [v for v in values if not math.isnan(v)]
    return sum(values) / len(values) if values else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run")
    parser.add_argument("--windows", default="0,10,30,60,90,120", help="window edges in s of process time")
    parser.add_argument("--target", type=float, default=300e3, help="force target in N")
    args = parser.parse_args()
    h = load_history(args.run)
    edges = [float(e) for e in args.windows.split(",")]
    t_last = h["process_time_s"][-1]
    print(f"{args.run}: {len(h['process_time_s'])} rows up to {t_last:.2f} s of process")
    header = ("window_s", "force_kN", "rmse_kN", "v_die_mm_s", "interface_K", "die_tc_K", "plastic_W",
              "friction_W", "die_contacts", "sticking", "max_kin_int", "rod_mm")
    print(" ".join(f"{c:>12}" for c in header))
    for t0, t1 in zip(edges[:-1], edges[1:]):
        if t0 >= t_last:
            break
        rows = window_rows(h, t0, min(t1, t_last))
        if len(rows) < 2:
            continue
        first, last = rows[0], rows[-1]
        force = [h["extrusion_force_N"][i] for i in rows]
        rmse = math.sqrt(mean([(f - args.target) ** 2 for f in force]))
        dt = h["process_time_s"][last] - h["process_time_s"][first]
        velocity = (h["die_displacement_m"][last] - h["die_displacement_m"][first]) / dt
        values = (f"{t0:g}-{h['process_time_s'][last]:.4g}", f"{mean(force) / 1e3:.2f}", f"{rmse / 1e3:.2f}",
                  f"{velocity * 1e3:.4f}", f"{mean([h['interface_temperature_K'][i] for i in rows]):.1f}",
                  f"{mean([h['die_thermocouple_K'][i] for i in rows]):.1f}",
                  f"{mean([h['plastic_heat_rate_W'][i] for i in rows]):.1f}",
                  f"{mean([h['friction_heat_rate_W'][i] for i in rows]):.1f}",
                  f"{mean([h['die_contacts_1'][i] for i in rows]):.1f}",
                  f"{mean([h['die_sticking_fraction_1'][i] for i in rows]):.3f}",
                  f"{max(h['kinetic_to_internal_ratio_1'][i] for i in rows):.2e}",
                  f"{h['rod_length_m'][last] * 1e3:.2f}")
        print(" ".join(f"{v:>12}" for v in values))
    tracers = sorted({k.split("_")[1] for k in h if k.startswith("tracer_") and k.endswith("plastic_strain_1")})
    print("tracer plastic strain at the last row: " + ", ".join(
        f"{p} {h[f'tracer_{p}_plastic_strain_1'][-1]:.3f}" for p in tracers))
    print(f"die displacement at the last row: {h['die_displacement_m'][-1] * 1e3:.3f} mm")


if __name__ == "__main__":
    main()
