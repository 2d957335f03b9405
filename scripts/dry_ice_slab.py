#!/usr/bin/env python3
"""Slab (Sachs) estimate of the dry-ice ram force for the 13 dies (docs/theory.md eq. 88), an analytic
yardstick for the SPH F_L of docs/validation/dry_ice.md. Same model as the cases: elastic-perfectly-
plastic, sigma_y = 3.5 MPa, Coulomb mu = 0.1, barrel D = 28 mm, outlet d = 16 mm, die profiles of
eqs. 83-84 (WK outward, WP inward), billet H_1 above the die entry (--billet, mm; default the cases').

What the estimate leaves out, so it is a lower estimate of a fully plastic flow, not a bound: redundant
shear at the die entry and exit, friction in the land (the extrudate leaves the cone at zero axial
stress), elastic springback. Prints one row per die and the ratio to the experimental median.

  python3 scripts/dry_ice_slab.py [--billet 80]
"""
import argparse
import csv
import json
import math
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MU, SIGMA_Y, NU = 0.1, 3.5e6, 0.46
D, D_OUT = 28e-3, 16e-3
R0, R1 = D / 2, D_OUT / 2


def profile(row):
    """Die wall radius r(z) for 0 <= z <= h, z measured down from the die entry; returns (h, r)."""
    family = row["family"]
    if family == "CS":
        h = float(row["cone_length_mm"]) * 1e-3
        return h, lambda z: R0 - (R0 - R1) * z / h
    h1 = float(row["h1_mm"] or 0) * 1e-3
    h2 = float(row["h2_mm"] or 0) * 1e-3
    rk = float(row["R1_mm"] or 0) * 1e-3
    rp = float(row["R2_mm"] or 0) * 1e-3
    h = h1 + h2

    def r(z):
        if z <= h1:  # convex arc, tangent to the barrel at the entry (eq. 83, outward)
            return R0 - rk + math.sqrt(max(rk * rk - z * z, 0.0))
        return R1 + rp - math.sqrt(max(rp * rp - (h - z) ** 2, 0.0))  # concave, tangent to the land

    return h, r


def entry_stress(row, steps=20000):
    """Axial stress at the die entry: eq. 88 integrated upstream from the exit, where it is zero."""
    h, r = profile(row)
    dz = h / steps
    sigma = 0.0
    for i in range(steps):
        z = h - (i + 0.5) * dz
        tan_a = (r(max(z - dz / 2, 0.0)) - r(min(z + dz / 2, h))) / dz
        sigma += dz * (2.0 / r(z)) * (MU * sigma + SIGMA_Y * (tan_a + MU))
    return sigma


def cases_billet_mm():
    """The bundled cases' billet height above the die entry (every die shares it), read from a case file
    so that the default follows the cases."""
    with open(os.path.join(ROOT, "cases", "ram_extrusion", "dry_ice", "dry_ice_CS50.json")) as f:
        value, unit = json.load(f)["process"]["billet_height"].split()
    if unit != "mm":
        raise SystemExit(f"dry_ice_CS50.json: /process/billet_height in {unit}, expected mm")
    return float(value)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--billet", type=float, default=cases_billet_mm(),
                        help="billet height above the die entry, mm (default: the bundled cases')")
    h_billet = parser.parse_args().billet * 1e-3
    with open(os.path.join(ROOT, "cases", "ram_extrusion", "reference", "dry_ice_dies.csv"), newline="") as f:
        dies = list(csv.DictReader(f))
    with open(os.path.join(ROOT, "cases", "ram_extrusion", "reference", "dry_ice_force_public.csv"), newline="") as f:
        exp = {r["die"]: float(r["F_L_exp_median_N"]) for r in csv.DictReader(f)}
    area = math.pi * D * D / 4
    print("| die | entry stress (MPa) | F, elastic billet (N) | F, plastic billet (N) | exp. median (N) | plastic / exp. |")
    print("|---|---|---|---|---|---|")
    for row in dies:
        s = entry_stress(row)
        # The billet above the entry: wall pressure K sigma, K = nu / (1 - nu) when it is elastic and
        # confined, K = 1 when it yields (p = sigma + sigma_y, the sigma_y dropped): eq. 88b.
        f_el = s * math.exp(4 * MU * NU / (1 - NU) * h_billet / D) * area
        f_pl = s * math.exp(4 * MU * h_billet / D) * area
        e = exp.get(row["die"])
        measured = f"{e:.0f} | {f_pl / e:.2f}" if e else "held out |"
        print(f"| {row['die']} | {s / 1e6:.2f} | {f_el:.0f} | {f_pl:.0f} | {measured} |")


if __name__ == "__main__":
    main()
