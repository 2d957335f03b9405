#!/usr/bin/env python3
"""Where a friction-extrusion rod's material comes from (issue 8 item 5, "rod surface material comes
from the billet top"; docs/validation/friction_extrusion.md). Reads the first and one later particle
frame of a run, finds the rod (billet particles above the die face), splits it into its surface (the
outermost ring, r > orifice radius - spacing) and its core, and prints for each the depth below the
billet's top and the radius at which its particles started (followed by particle id).

The die face is the die body's lowest particle plus half a spacing (the die's thermal particles sit
half a spacing behind the face, theory eq. 90); the billet top at t = 0 is its highest particle plus
half a spacing.

usage: scripts/fe_rod_origin.py RUN [--frame N] [--orifice-radius 7e-3]
(default frame: the last particles_NNNNNN.vtu; needs python3-vtk9 and numpy)
"""
import argparse
import glob

import numpy as np

from run_output import read_frame

BILLET, DIE = 0, 1  # body indices of the friction_extrusion scene (billet, die, container)


def lattice_spacing(z):
    levels = np.unique(np.round(z, 9))
    steps = np.diff(levels)
    return float(steps[steps > 1e-9].min())


def describe(label, depth, radius, spacing):
    if depth.size == 0:
        print(f"{label}: none")
        return
    q = np.percentile(depth * 1e3, [10, 50, 90])
    top = np.mean(depth < spacing)
    top2 = np.mean(depth < 2 * spacing)
    print(f"{label}: {depth.size} particles; start depth below the billet top (mm) p10 {q[0]:.2f}, "
          f"median {q[1]:.2f}, p90 {q[2]:.2f}; from the top layer {100 * top:.0f} %, top two layers "
          f"{100 * top2:.0f} %; start radius median {np.median(radius) * 1e3:.2f} mm "
          f"(range {radius.min() * 1e3:.2f}-{radius.max() * 1e3:.2f})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run")
    parser.add_argument("--frame", type=int, help="frame number (default: the last)")
    parser.add_argument("--orifice-radius", type=float, default=7e-3, help="m (the bundled case: 7 mm)")
    args = parser.parse_args()
    frames = sorted(glob.glob(f"{args.run}/particles_[0-9]*.vtu"))
    path = f"{args.run}/particles_{args.frame:06d}.vtu" if args.frame is not None else frames[-1]
    start, _ = read_frame(frames[0])
    now, t = read_frame(path)

    billet0 = start["body"] == BILLET
    spacing = lattice_spacing(start["position"][billet0, 2])
    top0 = start["position"][billet0, 2].max() + spacing / 2
    origin = {int(i): p for i, p in zip(start["id"][billet0], start["position"][billet0])}

    x = now["position"]
    face = x[now["body"] == DIE, 2].min() - spacing / 2
    rod = (now["body"] == BILLET) & (x[:, 2] > face)
    r_now = np.hypot(x[:, 0], x[:, 1])
    surface = rod & (r_now > args.orifice_radius - spacing)
    print(f"{path}: t = {t:.4g} s (simulated), spacing {spacing * 1e3:.3g} mm, die face z = {face * 1e3:.2f} mm, "
          f"billet top at t = 0 z = {top0 * 1e3:.2f} mm; rod {int(rod.sum())} particles, "
          f"up to {((x[rod, 2].max() - face) * 1e3 if rod.any() else 0):.2f} mm above the face")
    for label, mask in (("rod surface", surface), ("rod core", rod & ~surface)):
        p0 = np.array([origin[int(i)] for i in now["id"][mask]]).reshape(-1, 3)
        describe(label, top0 - p0[:, 2], np.hypot(p0[:, 0], p0[:, 1]), spacing)


if __name__ == "__main__":
    main()
