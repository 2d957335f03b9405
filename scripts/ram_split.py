#!/usr/bin/env python3
"""Split a ram-extrusion run's extrusion pressure into barrel, entry and land parts, from its VTU frames.

Benbow-Bridgwater writes P_ex = P_1 + P_2 (docs/theory.md eqs. 78, 78a): an entry term P_1 and the land
term P_2 = 4 (L/D) tau_w, which is the pressure at the top of the land. A `sphforge run` of a
ram_extrusion case records only their sum (plus barrel friction) as the ram pressure. This script
measures the parts in the frames particles_NNNNNN.vtu whose ram displacement lies in the steady window
(summary.json's, or --window):

  land P_2    the axial stress -sigma_zz = p - s_zz, volume-weighted over slabs |z - z_c| < dx/2 of the
              land's cross-section (r < D/2 + dx), slab centres 1 mm apart from 1 mm below the land top
              to 1 mm above the exit, fitted by a straight line and evaluated at the land top
  land top    the same stress in the slab centred on the land top, less P_2: the step the stress takes
              within dx of the entry corner, which the straight line leaves out
  barrel      axial contact force of the particles within 1.2 dx of the barrel wall, above z = 1 mm and
              more than 2 mm below the highest particle (the ram face), over the barrel area
  entry P_1   P_ex - barrel - P_2, with P_ex the history's extrusion pressure at the frame
  land        tau from the stress gradient, (D/4) d(-sigma_zz)/dz; tau from the wall, the land
              particles' axial contact force over the land's wall area; the land's speed (mass mean of
              -v_z; also of the particles within dx of the wall) and tau_w of the case's Navier law
              at that speed; the packing, sum(m/rho) of the
              land particles over the bore's volume (1 when the particles fill the bore at their
              own density); the contacts' coverage, their number times dx^2 over the land's wall
              area (each contact carries the wall stress over dx^2, eq. 18g), and their axial force
              over dx^2 times the Navier law at each contact's own slip (1 when the law holds)
  energy      (with --yield-stress, a perfectly plastic material) the ram's power split by where it
              goes, each as a pressure-equivalent, power / (A0 V_ram): plastic dissipation
              sigma_y sum V d(eps_p)/dt from consecutive frames (particles matched by id), the
              artificial terms (the history's internal-energy rate, eq. 27, less the plastic
              dissipation: artificial viscosity and stress, density diffusion, elastic storage), the
              friction heat of each tool, and the rest (contact damping, penalty springs, kinetic)
  cone        (with --cone-angle) the contact force of the particles within dx of a cone
              r = D/2 + (z - z_land_top) tan(theta) split into its normal and tangential parts; their
              axial shares over the barrel area, the mean tangential stress over the cone's area and
              the slip speed along it

Full-body values: forces are multiplied by the sector count (summary.json "symmetry.multiplier").
Positions in mm, z = 0 at the die face (cone top), the land from --land-top down to --land-exit.

usage: scripts/ram_split.py RUN_DIR --spacing 0.75 --land-top -11 --land-exit -23
           [--window 2 3] [--die-diameter 3] [--barrel-diameter 25] [--cone-angle 45]
           [--navier 1.8e4 5.4e5 0.58] [--yield-stress 0.38]
(needs numpy and VTK's Python module: python3-vtk9)
"""
import argparse
import json
import math
import re

import numpy as np

from run_output import frame_by_id, load_history, read_frame


def frames_in_window(run, history, u0, u1):
    """(ram displacement, P_ex, path, time) of each frame whose displacement lies in [u0, u1]."""
    t, u, p_ex = (np.array(history[k]) for k in ("time_s", "ram_displacement_m", "extrusion_pressure_Pa"))
    with open(f"{run}/particles.pvd") as f:
        listed = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', f.read())
    picked = []
    for ts, name in listed:
        uu = float(np.interp(float(ts), t, u))
        if u0 - 1e-12 <= uu <= u1 + 1e-12:
            picked.append((uu, float(np.interp(float(ts), t, p_ex)), f"{run}/{name}", float(ts)))
    return picked


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--spacing", type=float, required=True, help="particle spacing dx (mm)")
    ap.add_argument("--land-top", type=float, required=True, help="z of the land's top (mm)")
    ap.add_argument("--land-exit", type=float, required=True, help="z of the die exit (mm)")
    ap.add_argument("--window", type=float, nargs=2, help="ram displacement window (mm); default: summary.json's")
    ap.add_argument("--die-diameter", type=float, default=3.0, help="mm")
    ap.add_argument("--barrel-diameter", type=float, default=25.0, help="mm")
    ap.add_argument("--cone-angle", type=float, help="half-angle (deg) of a conical entry from the land top up")
    ap.add_argument("--yield-stress", type=float, help="sigma_y (MPa) of a perfectly plastic material: adds the energy split")
    ap.add_argument("--navier", type=float, nargs=3, default=(1.8e4, 5.4e5, 0.58),
                    metavar=("TAU0", "BETA", "N"), help="the case's Navier law tau_w = tau0 + beta v^n (SI)")
    a = ap.parse_args()

    with open(f"{a.run}/summary.json") as f:
        summary = json.load(f)
    sectors = summary.get("symmetry", {}).get("multiplier", 1.0)
    if a.window:
        u0, u1 = a.window[0] * 1e-3, a.window[1] * 1e-3
    else:
        u0, u1 = summary["metrics"]["steady_window_start_m"], summary["metrics"]["steady_window_end_m"]
    dx, z_top, z_exit = a.spacing * 1e-3, a.land_top * 1e-3, a.land_exit * 1e-3
    R0, Rd = 0.5e-3 * a.barrel_diameter, 0.5e-3 * a.die_diameter
    A0 = math.pi * R0 * R0
    tau0, beta, n_exp = a.navier
    tau_w = lambda v: tau0 + beta * max(v, 0.0) ** n_exp

    history = {k: np.array(v) for k, v in load_history(a.run).items()}
    t, u_hist = history["time_s"], history["ram_displacement_m"]
    in_window = (u_hist >= u0 - 1e-12) & (u_hist <= u1 + 1e-12)
    p_window = history["extrusion_pressure_Pa"][in_window].mean()
    v_window = history["extrudate_velocity_m_s"][in_window].mean()
    frames = frames_in_window(a.run, history, u0, u1)
    if not frames:
        raise SystemExit(f"{a.run}: no VTU frame with a ram displacement in {u0*1e3:g}-{u1*1e3:g} mm")
    slabs = np.arange(z_top - 1e-3, z_exit + 1e-3 - 1e-9, -1e-3)
    inner_length = z_top - z_exit - 2e-3
    rows = []
    plastic = []  # (total, above the land's top) plastic dissipation rate (W) between consecutive frames
    previous = None
    for u, p_ex, path, time in frames:
        f, _ = read_frame(path)
        if a.yield_stress:
            g = frame_by_id(f)
            state = (time, g["id"], g["plastic_strain"], g["mass"] / g["density"], g["position"][:, 2])
            if previous is not None and np.array_equal(previous[1], state[1]):
                work = 0.5 * (state[3] + previous[3]) * (state[2] - previous[2])  # V d(eps_p)
                above = 0.5 * (state[4] + previous[4]) > z_top  # where the particle was mid-interval
                scale = sectors * a.yield_stress * 1e6 / (time - previous[0])
                plastic.append((scale * work.sum(), scale * work[above].sum()))
            previous = state
        x, m, rho = f["position"], f["mass"], f["density"]
        volume = m / rho
        axial_stress = f["pressure"] - f["deviatoric_stress"][:, 2]  # -sigma_zz
        z, r = x[:, 2], np.hypot(x[:, 0], x[:, 1])
        fz = f["contact_force"][:, 2]
        bore = r < Rd + dx

        def slab_stress(zc):
            """-sigma_zz volume-weighted over the bore's slab |z - zc| < dx/2; NaN where it is empty."""
            s = bore & (np.abs(z - zc) < 0.5 * dx)
            return (volume[s] * axial_stress[s]).sum() / volume[s].sum() if s.any() else float("nan")

        centres, profile = [], []
        for zc in slabs:  # empty slabs (a land shorter than 2 mm plus dx, a gap) are skipped
            stress = slab_stress(zc)
            if not math.isnan(stress):
                centres.append(zc)
                profile.append(stress)
        if len(centres) < 2:
            raise SystemExit(f"{path}: fewer than two occupied slabs in the land; check --land-top and --land-exit")
        gradient, intercept = np.polyfit(centres, profile, 1)
        p2 = gradient * z_top + intercept
        # The slab centred on the land's top straddles the entry corner; its mean stress less the
        # fit's value there is the step the stress takes within dx of the corner.
        top_stress = slab_stress(z_top)
        barrel = (r > R0 - 1.2 * dx) & (z > 1e-3) & (z < z.max() - 2e-3)
        p_barrel = sectors * fz[barrel].sum() / A0
        land = bore & (z <= z_top - 1e-3) & (z >= z_exit + 1e-3)
        speed = -(m[land] * f["velocity"][land, 2]).sum() / m[land].sum()
        wall = land & (r > Rd - dx)  # the particles next to the land's wall
        wall_speed = -(m[wall] * f["velocity"][wall, 2]).sum() / m[wall].sum()
        # The land's contacts: each carries the wall law's stress times dx^2 (theory eq. 18g), so the
        # wall's force is (contacts x dx^2 / wall area) x the law's stress at the contacts' own slip.
        touching = wall & (np.abs(f["contact_force"]).sum(axis=1) > 0)
        slip = np.maximum(-f["velocity"][touching, 2], 0.0)
        row = {"u": u, "p_ex": p_ex, "barrel": p_barrel, "p2": p2, "p1": p_ex - p_barrel - p2, "top_step": top_stress - p2,
               "tau_gradient": gradient * Rd / 2, "speed": speed, "wall_speed": wall_speed,
               "tau_wall": sectors * fz[land].sum() / (2 * math.pi * Rd * inner_length),
               "packing": sectors * volume[land].sum() / (math.pi * Rd * Rd * inner_length),
               "coverage": sectors * touching.sum() * dx * dx / (2 * math.pi * Rd * inner_length),
               "law_ratio": fz[touching].sum() / (dx * dx * (tau0 + beta * slip ** n_exp).sum())
               if touching.any() else float("nan")}
        if a.cone_angle:
            th = math.radians(a.cone_angle)
            e_r = np.zeros_like(x[:, :2])
            nz = r > 0
            e_r[nz] = x[nz, :2] / r[nz, None]
            f_r = (f["contact_force"][:, :2] * e_r).sum(axis=1)
            v_r = (f["velocity"][:, :2] * e_r).sum(axis=1)
            # Distance from the cone r = Rd + (z - z_top) tan(th), positive inside the paste; the
            # inward normal is (-cos th, sin th) in (r, z), the tangent up the cone (sin th, cos th).
            dist = (Rd + (z - z_top) * math.tan(th) - r) * math.cos(th)
            cone_height = (R0 - Rd) / math.tan(th)
            s = (dist > -0.25 * dx) & (dist < dx) & (z > z_top + 0.5e-3) & (z < z_top + cone_height - 0.5e-3)
            f_n = -f_r[s] * math.cos(th) + fz[s] * math.sin(th)
            f_t = f_r[s] * math.sin(th) + fz[s] * math.cos(th)
            covered = (cone_height - 1e-3) / cone_height
            area = math.pi * (R0 + Rd) * cone_height / math.cos(th) * covered
            row.update({"cone_tau": sectors * f_t.sum() / area,
                        "cone_shear_axial": sectors * f_t.sum() * math.cos(th) / A0,
                        "cone_normal_axial": sectors * f_n.sum() * math.sin(th) / A0,
                        "cone_slip": -(v_r[s] * math.sin(th) + f["velocity"][s, 2] * math.cos(th)).mean()})
        rows.append(row)

    mean = {k: float(np.mean([row[k] for row in rows])) for k in rows[0]}
    sem = lambda k: float(np.std([row[k] for row in rows], ddof=1) / math.sqrt(len(rows))) if len(rows) > 1 else float("nan")
    print(f"{a.run}: {len(rows)} frames at u = {', '.join('%.2f' % (row['u'] * 1e3) for row in rows)} mm "
          f"(window {u0*1e3:g}-{u1*1e3:g} mm)")
    print(f"  P_ex: window mean {p_window/1e6:.3f} MPa (history), at the frames {mean['p_ex']/1e6:.3f} MPa")
    print(f"  barrel {mean['barrel']/1e6:.3f} MPa | land P_2 {mean['p2']/1e6:.3f} MPa (+-{sem('p2')/1e6:.3f}) | "
          f"entry P_1 {mean['p1']/1e6:.3f} MPa (+-{sem('p1')/1e6:.3f})  [+-: standard error over the frames]")
    print(f"  land top: -sigma_zz in the slab |z - z_top| < dx/2 exceeds P_2 by {mean['top_step']/1e6:.3f} MPa "
          f"(+-{sem('top_step')/1e6:.3f}): the step within dx of the entry corner")
    print(f"  land: tau from the stress gradient {mean['tau_gradient']/1e3:.1f} kPa, from the wall {mean['tau_wall']/1e3:.1f} kPa; "
          f"speed {mean['speed']:.4f} m/s (next to the wall {mean['wall_speed']:.4f}; V_ex {v_window:.4f}), tau_w there {tau_w(mean['speed'])/1e3:.1f} kPa; "
          f"packing {mean['packing']:.3f}")
    print(f"  land contacts: contacts x dx^2 / wall area {mean['coverage']:.3f}; their axial force against "
          f"dx^2 x the Navier law at each one's slip {mean['law_ratio']:.3f}")
    if a.yield_stress and plastic:
        ti = [frames[0][3], frames[-1][3]]
        rate = lambda k: sectors * (np.interp(ti[1], t, history[k]) - np.interp(ti[0], t, history[k])) / (ti[1] - ti[0])
        flux = A0 * (np.interp(ti[1], t, u_hist) - np.interp(ti[0], t, u_hist)) / (ti[1] - ti[0])
        work, internal = rate("tool_work_J"), rate("internal_energy_J")  # the rest holds the kinetic part
        sel = (t >= ti[0]) & (t <= ti[1])
        heat = {k[:-len("_friction_heat_W")]: sectors * v[sel].mean() for k, v in history.items() if k.endswith("_friction_heat_W")}
        dissipation = float(np.mean([p[0] for p in plastic]))
        dissipation_above = float(np.mean([p[1] for p in plastic]))
        mpa = lambda w: w / flux / 1e6
        print(f"  energy over u = {frames[0][0]*1e3:.2f}-{frames[-1][0]*1e3:.2f} mm, as pressure-equivalents (power / ram volume flux): "
              f"tool work {mpa(work):.3f} = plastic {mpa(dissipation):.3f} + artificial terms {mpa(internal - dissipation):.3f} + "
              + " + ".join(f"friction {k} {mpa(v):.3f}" for k, v in heat.items())
              + f" + rest {mpa(work - internal - sum(heat.values())):.3f} MPa (artificial share {100 * (internal - dissipation) / work:.0f} %)")
        print(f"  plastic dissipation above the land's top {mpa(dissipation_above):.3f} MPa, at and below it {mpa(dissipation - dissipation_above):.3f} MPa")
    if a.cone_angle:
        print(f"  cone: normal load {mean['cone_normal_axial']/1e6:.3f} MPa, shear {mean['cone_shear_axial']/1e6:.3f} MPa "
              f"(axial, over A0); mean shear stress {mean['cone_tau']/1e3:.1f} kPa; slip speed {mean['cone_slip']*1e3:.2f} mm/s "
              f"(tau_w there {tau_w(mean['cone_slip'])/1e3:.1f} kPa)")


if __name__ == "__main__":
    main()
