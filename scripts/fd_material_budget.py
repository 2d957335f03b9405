#!/usr/bin/env python3
"""Where the friction-drilled hole's material ends up: reads the first and last particle frames of a
`sphforge run` of the friction_drilling process, follows the sheet particles by id, and counts those
that started inside the drill's radius (the hole) by where they are at the end: above the upper
surface (upper bushing), still inside the sheet's thickness, below the lower surface in the bushing
band (lower bushing), or below it inside the drill's radius or far below the sheet (a cap pushed out
ahead of the tip, loose debris). docs/validation/friction_drilling.md, section "Bond failure and the
bushing", uses it.

    scripts/fd_material_budget.py RUN [--drill-radius 1.85e-3] [--band-outer 3.5e-3]
                                      [--thickness 1.2e-3] [--debris-depth 4e-3]
                                      [--route K [--time-scaling 100]]

--route K also prints, for every K-th frame, how many of the hole's particles are above the sheet,
still in the hole, pushed sideways into the sheet, below the sheet outside the drill's radius, and
below it inside that radius (a dome or cap ahead of the tip); and how far the upper surface near the
hole has moved (third-highest particle per ring, against its start).

Lengths in m; the sheet's upper surface is z = 0 (the process's frame). Counts are of the particles in
the run (a sector run counts its sector). Needs python3-vtk9 and numpy (scripts/run_output.py).
"""
import argparse
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_output import frame_by_id, read_frame  # noqa: E402


def third_highest(z):
    """The third-highest of z (one stray particle does not set a surface), NaN with fewer than three."""
    return np.sort(z)[-3] if len(z) >= 3 else float("nan")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run")
    p.add_argument("--drill-radius", type=float, default=1.85e-3, help="m (the M4 drill's cylinder)")
    p.add_argument("--band-outer", type=float, default=3.5e-3, help="m (bushing_outer_radius of eq. 127)")
    p.add_argument("--thickness", type=float, default=1.2e-3, help="m (sheet_thickness)")
    p.add_argument("--debris-depth", type=float, default=4e-3,
                   help="m below the upper surface beyond which a particle counts as debris")
    p.add_argument("--route", type=int, default=0, metavar="K",
                   help="also print, for every K-th frame, where the hole's particles are then")
    p.add_argument("--time-scaling", type=float, default=100.0,
                   help="numerics.time_scaling of the run, to print process time in the route")
    a = p.parse_args()

    frames = sorted(glob.glob(os.path.join(a.run, "particles_*.vtu")))
    if len(frames) < 2:
        sys.exit(f"{a.run}: needs at least two particle frames")
    first, _ = read_frame(frames[0])
    last, t = read_frame(frames[-1])
    f0, f1 = frame_by_id(first), frame_by_id(last)
    if not np.array_equal(f0["id"], f1["id"]):
        sys.exit("the first and last frames hold different particles")
    sheet = f0["body"] == 0
    r0 = np.hypot(f0["position"][:, 0], f0["position"][:, 1])
    r1 = np.hypot(f1["position"][:, 0], f1["position"][:, 1])
    z1 = f1["position"][:, 2]
    hole = sheet & (r0 < a.drill_radius)
    band = (r1 >= a.drill_radius) & (r1 <= a.band_outer)
    below = z1 < -a.thickness
    debris = below & ((r1 < a.drill_radius) | (z1 <= -a.debris_depth))
    places = [
        ("above the upper surface (upper bushing)", z1 > 0.0),
        ("inside the sheet's thickness, in the band", (z1 <= 0.0) & ~below & band),
        ("inside the sheet's thickness, outside the band", (z1 <= 0.0) & ~below & ~band),
        ("below the sheet, in the band (lower bushing)", below & band & ~debris),
        ("below the sheet, outside the band", below & ~band & ~debris),
        ("cap or debris (inside the drill radius, or deeper)", debris),
    ]
    print(f"{frames[-1]} (t = {t:.6g} s): {hole.sum()} sheet particles started inside r < {a.drill_radius * 1e3:.3g} mm")
    print(f"{'where at the end':52s} {'from the hole':>14s} {'share':>7s} {'all sheet':>10s}")
    for name, where in places:
        n = int(np.sum(hole & where))
        print(f"{name:52s} {n:14d} {n / max(hole.sum(), 1):7.1%} {int(np.sum(sheet & where)):10d}")
    if a.route > 0:
        print(f"route of the hole's particles (process time = simulated time x {a.time_scaling:g}):")
        print(f"{'process t (s)':>13s} {'above':>6s} {'in the hole':>12s} {'sheet, r>=R':>12s} {'below, r>=R':>12s} "
              f"{'below, r<R':>11s}  upper surface, r = R .. R + 2.65 mm (mm)")
        # The upper surface near the hole: the third-highest sheet particle centre in rings of
        # 0.4-0.5 mm (one stray particle does not set it, as in eq. 127), each against its start.
        rings = a.drill_radius + np.array([0.0, 0.4, 0.8, 1.2, 1.65, 2.15, 2.65]) * 1e-3
        ring_pairs = list(zip(rings[:-1], rings[1:]))
        z0 = f0["position"][:, 2]
        tops0 = [third_highest(z0[sheet & (r0 >= lo) & (r0 < hi)]) for lo, hi in ring_pairs]
        for path in frames[:: a.route] + ([frames[-1]] if (len(frames) - 1) % a.route else []):
            frame, tf = read_frame(path)
            fk = frame_by_id(frame)
            rk = np.hypot(fk["position"][:, 0], fk["position"][:, 1])
            zk = fk["position"][:, 2]
            inside, under = rk < a.drill_radius, zk < -a.thickness
            within = (zk <= 0.0) & ~under
            counts = [hole & (zk > 0.0), hole & within & inside, hole & within & ~inside, hole & under & ~inside,
                      hole & under & inside]
            near = sheet & (zk > -a.thickness - a.debris_depth)
            tops = [(third_highest(zk[near & (rk >= lo) & (rk < hi)]) - top0) * 1e3
                    for (lo, hi), top0 in zip(ring_pairs, tops0)]
            print(f"{tf * a.time_scaling:13.2f} " + " ".join(f"{int(c.sum()):{w}d}" for c, w in zip(counts, (6, 12, 12, 12, 11)))
                  + "  " + " ".join(f"{v:+.2f}" for v in tops))
    # The lower bushing's wall by depth: its particles' radial extent, plus one spacing for the
    # half spacing each particle reaches beyond its centre.
    dx = float(np.median(np.cbrt(f0["mass"][sheet] / f0["density"][sheet])))
    wall = sheet & below & band & ~debris
    print(f"lower bushing wall by depth below the lower surface (dx = {dx * 1e3:.3g} mm):")
    depth = -a.thickness - z1
    for lo in np.arange(0.0, depth[wall].max() + a.thickness / 3, a.thickness / 3) if wall.any() else []:
        m = wall & (depth >= lo) & (depth < lo + a.thickness / 3)
        if m.any():
            print(f"  {lo * 1e3:4.2f}-{(lo + a.thickness / 3) * 1e3:4.2f} mm: {int(m.sum()):5d} particles, "
                  f"r {r1[m].min() * 1e3:.2f}-{r1[m].max() * 1e3:.2f} mm, wall {(r1[m].max() - r1[m].min() + dx) * 1e3:.2f} mm")


if __name__ == "__main__":
    main()
