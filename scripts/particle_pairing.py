#!/usr/bin/env python3
"""How many particles of a body have a neighbour much closer than the lattice spacing: the signature of
the tensile instability (particles pairing up, docs/theory.md eq. 9) in a particle frame.

    scripts/particle_pairing.py RUN --spacing 0.4e-3 [--body 0] [--below 0.6] [--frame particles_000045.vtu]

Prints, for the last frame of RUN (or --frame), the distance of each particle of the body to its nearest
neighbour over dx (minimum, 1st and 5th percentile, median), the fraction closer than --below dx, and
where those particles are (radius and height, mm) with their median plastic strain and failed flag.
Used in docs/validation/friction_drilling.md ("What the peak force, the thermocouple and the bushing do
not depend on"). Needs numpy and python3-vtk9 (run_output.read_frame); no scipy: the nearest neighbours
come from a cell grid of edge 2 dx.
"""
import argparse
import glob
import os

import numpy as np

from run_output import read_frame


def nearest_neighbour_distance(x, cell):
    """Distance of every point of x (n x 3) to its nearest other point; exact when that distance is at
    most `cell` (points farther from every other point get the nearest within their 27 cells, or inf)."""
    keys = np.floor(x / cell).astype(np.int64)
    order = np.lexsort(keys.T)
    buckets = {}
    for i in order:
        buckets.setdefault(tuple(keys[i]), []).append(i)
    best = np.full(len(x), np.inf)
    offsets = [(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)]
    for key, members in buckets.items():
        members = np.array(members)
        near = [j for o in offsets for j in buckets.get((key[0] + o[0], key[1] + o[1], key[2] + o[2]), [])]
        near = np.array(near)
        d = np.linalg.norm(x[members, None, :] - x[None, near, :], axis=2)
        d[members[:, None] == near[None, :]] = np.inf
        best[members] = d.min(axis=1)
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run", help="output folder of `sphforge run`")
    ap.add_argument("--spacing", type=float, required=True, help="lattice spacing dx (m)")
    ap.add_argument("--body", type=int, default=0, help="body index (field `body`; 0: the first body)")
    ap.add_argument("--below", type=float, default=0.6, help="count particles closer than this many dx")
    ap.add_argument("--frame", help="frame file name in RUN (default: the last particles_*.vtu)")
    a = ap.parse_args()
    path = os.path.join(a.run, a.frame) if a.frame else sorted(glob.glob(os.path.join(a.run, "particles_*.vtu")))[-1]
    fields, time = read_frame(path)
    mask = fields["body"] == a.body if "body" in fields else np.ones(len(fields["position"]), bool)
    x = fields["position"][mask]
    nn = nearest_neighbour_distance(x, 2.0 * a.spacing) / a.spacing
    close = nn < a.below
    print(f"{path} (t = {time:.6g} s), body {a.body}: {len(x)} particles")
    print(f"nearest neighbour / dx: min {nn.min():.3f}, p1 {np.percentile(nn, 1):.3f}, p5 {np.percentile(nn, 5):.3f}, "
          f"median {np.median(nn):.3f}; closer than {a.below} dx: {close.sum()} ({100 * close.mean():.1f} %)")
    if close.any():
        r = np.hypot(x[close, 0], x[close, 1]) * 1e3
        z = x[close, 2] * 1e3
        print(f"  those particles: r {r.min():.2f}-{r.max():.2f} mm, z {z.min():.2f}-{z.max():.2f} mm")
        for name in ("plastic_strain", "failed", "temperature"):
            if name in fields:
                print(f"  median {name}: {np.median(fields[name][mask][close]):.3g} (whole body {np.median(fields[name][mask]):.3g})")


if __name__ == "__main__":
    main()
