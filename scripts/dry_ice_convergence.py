#!/usr/bin/env python3
"""Convergence in the spacing of one dry-ice die from `sphforge run` folders at several spacings
(docs/validation/dry_ice.md, "A fourth spacing, 0.5 mm").

    python3 scripts/dry_ice_convergence.py [--travel 2.0] [--window 1.5 2.0] [--measured 31.58] \
        2=RUN_2MM 1=RUN_1MM 0.6667=RUN_2_3MM 0.5=RUN_0_5MM

Per run (history.csv): the largest ram force over the first TRAVEL mm of ram travel and where it is,
the mean ram force over the rows in WINDOW (mm of travel), the barrel's share of the ram force over
min(1 mm, TRAVEL / 2) .. TRAVEL (barrel_force_z_N times summary.json's sector_count over ram_force_N:
the tool forces are the sector's, the ram force the full circle's), and over WINDOW the mean barrel
and die forces (z, full circle) and the axial stress at 1.5 R0 above the die entry
(section_pressure_Pa). The runs may have different strokes; only rows with u <= TRAVEL count, so
every run is read over the same travel.

Then, for both ram-force measures and for the window's barrel force, die force and section stress,
the observed order p and the limit F0 of F(h) = F0 + C h^p through the three finest spacings
(docs/validation/dry_ice.md; p solves (F1 - F2) / (F2 - F3) = (h1^p - h2^p) / (h2^p - h3^p)), and
the limits with p = 1 and p = 2 from the two finest. No order exists when the quantity is not
monotone in the spacing, no positive one when it changes by more per unit of log spacing at the
finer pair than at the coarser one, and an order below 0.5 says the spacings are not
in the asymptotic range; each is printed instead of a limit.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_output import load_history  # noqa: E402


def read_run(run, travel_mm, window_mm):
    if not os.path.exists(f"{run}/summary.json"):
        sys.exit(f"{run}: no summary.json (the run has not ended), so no sector count")
    with open(f"{run}/summary.json") as f:
        sectors = json.load(f)["metrics"].get("sector_count", 1.0)
    h = load_history(run)
    u = [x * 1e3 for x in h["ram_displacement_m"]]
    rows = [i for i, x in enumerate(u) if x <= travel_mm + 1e-9]
    if not rows or u[rows[-1]] < window_mm[1] - 0.05:
        sys.exit(f"{run}: reaches {max(u):.2f} mm of ram travel, the window ends at {window_mm[1]} mm")
    F = h["ram_force_N"]
    peak = max(rows, key=lambda i: F[i])
    win = [i for i in rows if window_mm[0] <= u[i] <= window_mm[1]]
    share_rows = [i for i in rows if u[i] >= min(1.0, travel_mm / 2)]
    share = sum(-h["barrel_force_z_N"][i] * sectors for i in share_rows) / sum(F[i] for i in share_rows)
    # Means over the window (NaN where an older history lacks the column): the ram force (the plateau)
    # and where it goes, the barrel's friction and the die's resistance (z forces on the tools, the
    # sector's times the sector count), and the axial stress at 1.5 R0 above the die entry.
    win_mean = lambda key, scale=1.0: (sum(h[key][i] for i in win) * scale / len(win)) if key in h else float("nan")
    return {"peak": F[peak], "at": u[peak], "plateau": win_mean("ram_force_N"), "rows": len(win),
            "share": share, "barrel": win_mean("barrel_force_z_N", -sectors),
            "die": win_mean("die_force_z_N", -sectors), "section": win_mean("section_pressure_Pa")}


def observed_order(h, F):
    """p of F = F0 + C h^p through three spacings h[0] > h[1] > h[2], for F monotone in h; None if no
    positive p fits."""
    r = (F[0] - F[1]) / (F[1] - F[2])
    ratio = lambda p: (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p)
    lo, hi = 1e-6, 20.0  # ratio(p) rises monotonically with p for h[0] > h[1] > h[2]
    if not ratio(lo) < r < ratio(hi):
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ratio(mid) < r else (lo, mid)
    return 0.5 * (lo + hi)


def limit(h, F, p):
    """F0 through the two finest spacings for order p."""
    C = (F[1] - F[2]) / (h[1] ** p - h[2] ** p)
    return F[2] - C * h[2] ** p


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", help="DX_MM=RUN_FOLDER, one per spacing")
    ap.add_argument("--travel", type=float, default=2.0, help="ram travel read from every run (mm)")
    ap.add_argument("--window", type=float, nargs=2, default=[1.5, 2.0], help="plateau window (mm of travel)")
    ap.add_argument("--measured", type=float, help="the measured F_L (kN), for the errors")
    a = ap.parse_args()
    try:
        runs = sorted(((float(s.split("=", 1)[0]), s.split("=", 1)[1]) for s in a.runs), reverse=True)
    except (ValueError, IndexError):
        ap.error("each run is DX_MM=RUN_FOLDER, e.g. 0.5=runs/CS50_dx0.5")
    data = [(dx, read_run(run, a.travel, a.window)) for dx, run in runs]
    err = lambda F: f" ({(F / a.measured - 1) * 100:+.1f} %)" if a.measured else ""
    for dx, d in data:
        print(f"dx {dx:.4g} mm: largest (u <= {a.travel:g} mm) {d['peak'] / 1e3:.2f} kN{err(d['peak'] / 1e3)} "
              f"at {d['at']:.2f} mm; mean {a.window[0]:g}-{a.window[1]:g} mm {d['plateau'] / 1e3:.2f} kN "
              f"({d['rows']} rows); barrel share {d['share'] * 100:.1f} %")
        print(f"    over {a.window[0]:g}-{a.window[1]:g} mm: barrel {d['barrel'] / 1e3:.2f} kN, die {d['die'] / 1e3:.2f} kN, "
              f"section at 1.5 R0 {d['section'] / 1e6:.2f} MPa")
    if len(data) < 3:
        return
    h = [dx for dx, _ in data[-3:]]
    for key, name, scale, unit in (("peak", "largest", 1e-3, "kN"), ("plateau", "plateau", 1e-3, "kN"),
                                   ("barrel", "barrel over the window", 1e-3, "kN"),
                                   ("die", "die over the window", 1e-3, "kN"),
                                   ("section", "section over the window", 1e-6, "MPa")):
        F = [d[key] * scale for _, d in data[-3:]]
        # The errors against the measurement belong to the ram force only.
        e = err if key in ("peak", "plateau") else (lambda F: "")
        if any(x != x for x in F):
            print(f"{name}: not in every history")
            continue
        monotone = (F[0] - F[1]) * (F[1] - F[2]) > 0
        p = observed_order(h, F) if monotone else None
        if not monotone:
            head = f"{name}: not monotone in the spacing, no order"
        elif p is None:
            head = (f"{name}: no positive order "
                    "(it changes by more per unit of log spacing at the finer pair)")
        elif p < 0.5:
            head = f"{name}: order {p:.2f}, too low to extrapolate (not in the asymptotic range)"
        else:
            head = f"{name}: order {p:.2f}, limit {limit(h, F, p):.2f} {unit}{e(limit(h, F, p))}"
        print(f"{head}; p = 1: {limit(h, F, 1):.2f} {unit}{e(limit(h, F, 1))}; "
              f"p = 2: {limit(h, F, 2):.2f} {unit}{e(limit(h, F, 2))}")


if __name__ == "__main__":
    main()
