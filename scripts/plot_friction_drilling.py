#!/usr/bin/env python3
"""Plots friction-drilling histories (history.csv of `sphforge run`) against the unscaled process time
as an SVG with four panels: axial force, torque, thermocouple and maximum sheet temperature, bushing
lengths. No plotting library needed (plain SVG), so it runs wherever Python 3 does.

usage: plot_friction_drilling.py OUT.svg LABEL=RUN_DIR [LABEL=RUN_DIR ...]
Experimental references (cases/friction_drilling/reference/friction_drilling.md) are drawn as dashed
lines: 639 N, 445 degC, 4.34 mm.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_output import load_history  # noqa: E402

PANELS = [
    ("axial force (N)", lambda h, i: h["axial_force_N"][i], 639.0),
    ("torque (N m)", lambda h, i: h["torque_Nm"][i], None),
    ("thermocouple, 4 mm (degC)", lambda h, i: h["probe_temperature_K"][i] - 273.15, 445.0),
    ("bushing length, total (mm)", lambda h, i: 1e3 * h["bushing_total_m"][i], 4.34),
]
COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"]
W, H, ML, MR, MT, MB = 520, 260, 70, 20, 30, 40


def nice_max(v):
    if v <= 0:
        return 1.0
    e = 10 ** math.floor(math.log10(v))
    for m in (1, 2, 2.5, 5, 10):
        if m * e >= v:
            return m * e
    return 10 * e


def main():
    out, runs = sys.argv[1], [a.split("=", 1) for a in sys.argv[2:]]
    data = []
    for label, folder in runs:
        # load_history drops a partly written last row; rows without a bushing measurement are skipped.
        h = load_history(folder)
        rows = [i for i, b in enumerate(h["bushing_total_m"]) if not math.isnan(b)]
        data.append((label, [h["process_time_s"][i] for i in rows], (h, rows)))
    tmax = nice_max(max(max(t) for _, t, _ in data))
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * W}" height="{2 * H + 30}" font-family="sans-serif" font-size="12">',
           '<rect width="100%" height="100%" fill="white"/>']
    for k, (title, get, ref) in enumerate(PANELS):
        ox, oy = (k % 2) * W, (k // 2) * H + 30
        values = [[get(h, i) for i in rows] for _, _, (h, rows) in data]
        vmax = nice_max(max([max(v) for v in values] + [ref or 0.0]) * 1.05)
        px = lambda t: ox + ML + (W - ML - MR) * t / tmax
        py = lambda v: oy + H - MB - (H - MT - MB) * max(0.0, v) / vmax
        svg.append(f'<rect x="{ox + ML}" y="{oy + MT}" width="{W - ML - MR}" height="{H - MT - MB}" fill="none" stroke="black"/>')
        svg.append(f'<text x="{ox + ML}" y="{oy + MT - 8}">{title}</text>')
        for i in range(6):
            t, v = tmax * i / 5, vmax * i / 5
            svg.append(f'<text x="{px(t):.1f}" y="{oy + H - MB + 15}" text-anchor="middle">{t:g}</text>')
            svg.append(f'<text x="{ox + ML - 5}" y="{py(v) + 4:.1f}" text-anchor="end">{v:g}</text>')
        svg.append(f'<text x="{ox + ML + (W - ML - MR) / 2}" y="{oy + H - 8}" text-anchor="middle">process time (s)</text>')
        if ref is not None:
            svg.append(f'<line x1="{px(0):.1f}" y1="{py(ref):.1f}" x2="{px(tmax):.1f}" y2="{py(ref):.1f}" stroke="gray" stroke-dasharray="5,4"/>')
        for j, ((label, t, _), v) in enumerate(zip(data, values)):
            pts = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in zip(t, v))
            svg.append(f'<polyline points="{pts}" fill="none" stroke="{COLOURS[j % 5]}" stroke-width="1.2"/>')
    for j, (label, _, _) in enumerate(data):
        svg.append(f'<text x="{ML + 220 * j}" y="16" fill="{COLOURS[j % 5]}">{label}</text>')
    svg.append(f'<text x="{ML + 220 * len(data)}" y="16" fill="gray">- - experiment</text>')
    svg.append("</svg>")
    open(out, "w").write("\n".join(svg))


if __name__ == "__main__":
    main()
