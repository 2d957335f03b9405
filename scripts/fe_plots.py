#!/usr/bin/env python3
"""History plots of friction_extrusion runs (docs/validation/friction_extrusion.md): extrusion force
against the target, die displacement and plunge velocity, temperatures (interface, die thermocouple,
billet thermocouples) and heat rates, against process time. Several runs are overlaid.

usage: scripts/fe_plots.py OUT_PREFIX LABEL=RUN_DIR [LABEL=RUN_DIR ...]
writes OUT_PREFIX_force.png, _displacement.png, _temperature.png, _heat.png (needs matplotlib)
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from run_output import load_history  # noqa: E402


def main(prefix, runs):
    data = [(label, load_history(run)) for label, run in runs]
    figs = {
        "force": [("extrusion_force_N", 1e-3, "extrusion force (kN)"), ("extrusion_torque_Nm", 1.0, "die torque (N m)")],
        "displacement": [("die_displacement_m", 1e3, "die displacement (mm)"),
                         ("die_plunge_velocity_m_s", 1e3, "die plunge velocity (mm/s)")],
        "temperature": [("interface_temperature_K", 1.0, "interface T (K)"), ("die_thermocouple_K", 1.0, "die thermocouple (K)")],
        "heat": [("plastic_heat_rate_W", 1e-3, "plastic heat (kW)"), ("friction_heat_rate_W", 1e-3, "friction heat (kW)")],
    }
    for name, series in figs.items():
        fig, axes = plt.subplots(len(series), 1, figsize=(8, 3 * len(series)), sharex=True)
        for ax, (col, scale, ylabel) in zip(axes, series):
            for label, h in data:
                if col in h:
                    ax.plot(h["process_time_s"], [v * scale for v in h[col]], label=label, lw=1)
            if col == "extrusion_force_N":
                h = data[0][1]
                if "fe_pid_target_N" in h:
                    ax.plot(h["process_time_s"], [v * scale for v in h["fe_pid_target_N"]], "k--", lw=0.8, label="target")
            if name == "temperature" and col == "interface_temperature_K":
                ax.axhspan(623.15, 723.15, color="0.9", label="paper 350-450 C")
            ax.set_ylabel(ylabel)
            ax.grid(True, lw=0.3)
            ax.legend(fontsize=7)
        if name == "temperature":
            fig2, ax2 = plt.subplots(figsize=(8, 4))
            for label, h in data:
                for col in [c for c in h if c.startswith("billet_tc_")]:
                    ax2.plot(h["process_time_s"], h[col], lw=0.8, label=f"{label} {col[10:-2]}")
            ax2.set_xlabel("process time (s)")
            ax2.set_ylabel("billet thermocouples (K)")
            ax2.legend(fontsize=6, ncol=3)
            ax2.grid(True, lw=0.3)
            fig2.tight_layout()
            fig2.savefig(f"{prefix}_billet_thermocouples.png", dpi=90)
        axes[-1].set_xlabel("process time (s)")
        fig.tight_layout()
        fig.savefig(f"{prefix}_{name}.png", dpi=90)
        print(f"{prefix}_{name}.png")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], [a.split("=", 1) for a in sys.argv[2:]])
