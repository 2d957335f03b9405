#!/usr/bin/env python3
"""The extruded wire (rod) of a friction_extrusion run from its last particle frame (or frame K):
plastic strain against radius (centre against periphery) and the wire's continuity along its axis.
Used for FSBE, issue item 6 (docs/validation/friction_extrusion.md, FSBE section).

Wire particles: billet particles (body 0) above the die face (history column die_position_m at the
frame's time) and inside the bore radius + dx/2. Continuous: no axial gap between consecutive wire
particles wider than 1.5 dx (the lattice neighbours are dx apart; a missing particle leaves 2 dx).

usage: scripts/fe_wire.py RUN_DIR BORE_RADIUS_MM DX_MM [FRAME_INDEX]   (needs python3-vtk9 and numpy)
"""
import glob
import sys

import numpy as np

from run_output import load_history, read_frame


def main(run, bore_radius, dx, frame=-1):
    frames = sorted(glob.glob(f"{run}/particles_*.vtu"))
    if not frames:
        sys.exit(f"{run}: no particles_*.vtu frames")
    d, t = read_frame(frames[frame])
    history = load_history(run)
    k = int(np.argmin(np.abs(np.array(history["time_s"]) - t)))  # the history row nearest the frame
    face = history["die_position_m"][k]
    x, body, eps = d["position"], d["body"], d["plastic_strain"]
    r = np.hypot(x[:, 0], x[:, 1])
    wire = (body == 0) & (x[:, 2] > face) & (r < bore_radius + 0.5 * dx)
    n = int(wire.sum())
    print(f"{frames[frame]}: process time {history['process_time_s'][k]:.2f} s, die face z = {face * 1e3:.2f} mm, "
          f"{n} wire particles")
    if n == 0:
        return
    z = np.sort(x[wire, 2]) - face
    gaps = np.diff(z)
    widest = gaps.max() if len(gaps) else 0.0
    print(f"  wire from {z[0] * 1e3:.2f} to {z[-1] * 1e3:.2f} mm above the face; widest axial gap "
          f"{widest * 1e3:.2f} mm; continuous (gaps < 1.5 dx = {1.5 * dx * 1e3:.2f} mm): {bool(widest < 1.5 * dx)}")
    big = np.where(gaps >= 1.5 * dx)[0]
    if len(big):
        print("  gaps >= 1.5 dx at (mm above the face, width mm): "
              + ", ".join(f"({z[k] * 1e3:.1f}, {gaps[k] * 1e3:.1f})" for k in big[:20]))
    edges = np.linspace(0.0, bore_radius + 0.5 * dx, 5)
    for lo, hi in zip(edges[:-1], edges[1:]):
        s = wire & (r >= lo) & (r < hi)
        if s.any():
            print(f"  r {lo * 1e3:4.2f}-{hi * 1e3:4.2f} mm: {int(s.sum()):5d} particles, plastic strain median "
                  f"{np.median(eps[s]):.3f}, mean {eps[s].mean():.3f}")
    centre, rim = wire & (r < 0.5 * bore_radius), wire & (r >= 0.5 * bore_radius)
    if centre.any() and rim.any():
        print(f"  median plastic strain: centre (r < {0.5 * bore_radius * 1e3:.2f} mm) {np.median(eps[centre]):.3f} "
              f"({int(centre.sum())}), periphery {np.median(eps[rim]):.3f} ({int(rim.sum())})")


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]) * 1e-3, float(sys.argv[3]) * 1e-3, int(sys.argv[4]) if len(sys.argv) == 5 else -1)
