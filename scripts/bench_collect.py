#!/usr/bin/env python3
"""Collect several `sphforge bench` folders (one case each) into one table and one plot for the docs.

Each bench folder has bench.json (per spacing: particles, steps, wall time, metrics and their relative
errors against the bench's reference). This script takes one metric and writes, for all folders:
  OUT.csv  case, spacing_m, particles_1, steps_1, wall_s, status, <metric>, <metric>_error_1 (signed:
           (value - reference) / reference), reference (the value, or "finest spacing"), source
           ("bench", or "sphforge run" for a row added with --run)
  OUT.png  |relative error| of the metric against wall time, one polyline per case (log-log); cases
           without a reference (errors against their own finest spacing) are drawn dashed
and prints a Markdown table (one row per case, one column group per spacing) on stdout.

usage: scripts/bench_collect.py --metric peak_force_N [--scale 1e-3 --unit kN]
           [--rows EARLIER.csv] [--run LABEL=SPACING_M:RUN_DIR ...] OUT [LABEL=BENCH_DIR ...]
--run adds a spacing that was not part of the bench but is the same case run by `sphforge run` (its
summary.json; the spacing is given because summary.json does not hold it), with the bench's reference:
a finer spacing that costs too much to run twice. A run continued with --restart counts the wall time of
all its parts (summary.json restart.wall_time_total_s).
--rows takes the rows of an earlier OUT.csv as they are (the same metric), for benches whose folders were
not kept; a bench folder or --run given as well adds to them.
(needs matplotlib for the plot)
"""
import argparse
import csv
import json
import math


def load(bench_dir):
    with open(f"{bench_dir}/bench.json") as f:
        return json.load(f)


def make_row(metric, label, spacing_m, particles, steps, wall_s, status, value, ref_value, ref_text, source):
    """One row of OUT.csv; the signed error is computed here only."""
    # Signed, unlike bench.json's |value - ref| / |ref|: whether a spacing over- or under-predicts matters.
    error = (value - ref_value) / ref_value if value is not None and ref_value else None
    return {"case": label, "spacing_m": spacing_m, "particles_1": particles, "steps_1": steps, "wall_s": wall_s,
            "status": status, metric: value, f"{metric}_error_1": error, "reference": ref_text, "source": source}


def rows_of(label, bench, metric):
    ref = bench["reference"]
    ref_value = ref.get("metrics", {}).get(metric)
    ref_text = f"{ref_value}" if ref.get("kind", "") == "file" and ref_value is not None else "finest spacing"
    return [make_row(metric, label, run["spacing_m"], run.get("particles"), run.get("steps"), run.get("wall_s"),
                     run.get("status"), run.get("metrics", {}).get(metric), ref_value, ref_text, "bench")
            for run in bench["runs"]]


def row_of_run(label, spacing_m, run_dir, bench_rows, metric):
    """One `sphforge run` folder as a row of the bench LABEL, against that bench's reference."""
    with open(f"{run_dir}/summary.json") as f:
        summary = json.load(f)
    ref_text = next(r["reference"] for r in bench_rows if r["case"] == label)
    # A bench without a reference file measures against its own finest spacing, which a finer added run
    # would not share: no error for that row.
    ref_value = float(ref_text) if ref_text != "finest spacing" else None
    # A restarted run's wall_time_s is its last part's; the whole run is what a spacing costs.
    wall_s = summary.get("restart", {}).get("wall_time_total_s", summary.get("wall_time_s"))
    return make_row(metric, label, spacing_m, summary.get("particles"), summary.get("steps"),
                    wall_s, summary.get("status"), summary.get("metrics", {}).get(metric),
                    ref_value, ref_text, "sphforge run")


def rows_of_csv(path, metric):
    """The rows of an earlier OUT.csv, numbers as numbers (empty cells as None)."""
    numeric = ["spacing_m", "particles_1", "steps_1", "wall_s", metric, f"{metric}_error_1"]
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if rows and metric not in rows[0]:
        raise SystemExit(f"--rows {path}: it has no column '{metric}'")
    def number(text):
        if text in ("", None):
            return None
        return int(text) if text.lstrip("-").isdigit() else float(text)
    for r in rows:
        for k in numeric:
            r[k] = number(r[k])
    return rows


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return ""
    return f"{x:.{digits}g}"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--metric", required=True)
    p.add_argument("--scale", type=float, default=1.0, help="factor applied to the metric in the table")
    p.add_argument("--unit", default="", help="unit of the scaled metric, written after each value in the table")
    p.add_argument("--run", action="append", default=[], metavar="LABEL=SPACING_M:RUN_DIR",
                   help="add a `sphforge run` folder of the same case as one more spacing of bench LABEL")
    p.add_argument("--rows", metavar="EARLIER_CSV", help="start from the rows of an earlier OUT.csv")
    p.add_argument("out")
    p.add_argument("benches", nargs="*", metavar="LABEL=BENCH_DIR")
    a = p.parse_args()
    if not a.benches and not a.rows:
        p.error("give bench folders, --rows, or both")

    all_rows = rows_of_csv(a.rows, a.metric) if a.rows else []
    for item in a.benches:
        label, _, folder = item.partition("=")
        all_rows += rows_of(label, load(folder), a.metric)
    for item in a.run:
        label, _, rest = item.partition("=")
        spacing, _, folder = rest.partition(":")
        if not any(r["case"] == label for r in all_rows):
            p.error(f"--run {item}: no bench is labelled '{label}'")
        all_rows.append(row_of_run(label, float(spacing), folder, all_rows, a.metric))
    # Coarsest first within each case, as bench orders its own runs.
    order = {c: i for i, c in enumerate(dict.fromkeys(r["case"] for r in all_rows))}
    all_rows.sort(key=lambda r: (order[r["case"]], -r["spacing_m"]))

    columns = ["case", "spacing_m", "particles_1", "steps_1", "wall_s", "status", a.metric, f"{a.metric}_error_1",
               "reference", "source"]
    with open(f"{a.out}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(all_rows)

    # Markdown: per case, value / error / wall at each spacing (coarsest first, as bench orders them).
    cases = list(dict.fromkeys(r["case"] for r in all_rows))
    spacings = sorted({r["spacing_m"] for r in all_rows}, reverse=True)
    head = "| case | reference | " + " | ".join(f"dx = {s * 1e3:g} mm: value, error, particles, wall" for s in spacings) + " |"
    print(head)
    print("|" + "---|" * (2 + len(spacings)))
    for c in cases:
        by_dx = {r["spacing_m"]: r for r in all_rows if r["case"] == c}
        ref = next(iter(by_dx.values()))["reference"]  # one reference per bench
        ref_text = fmt(float(ref) * a.scale, 4) + f" {a.unit}" if ref != "finest spacing" else "finest spacing"
        cells = []
        for s in spacings:
            r = by_dx.get(s)
            if r is None or r[a.metric] is None:
                cells.append(f"{r['status'] if r else 'not run'}")
                continue
            err = r[f"{a.metric}_error_1"]
            cells.append(f"{fmt(r[a.metric] * a.scale, 4)} {a.unit}, "
                         f"{(f'{100 * err:+.1f} %') if err is not None else '-'}, "
                         f"{int(r['particles_1']):,}, " + (f"{r['wall_s']:.0f} s" if r['wall_s'] is not None else "wall -"))
        print(f"| {c} | {ref_text} | " + " | ".join(cells) + " |")
    # Mean absolute error over the cases that have a reference of their own (a measurement, an analytic
    # value), per spacing: the figure an issue's "mean absolute error" target is stated in.
    for s in spacings:
        errs = [abs(r[f"{a.metric}_error_1"]) for r in all_rows
                if r["spacing_m"] == s and r["reference"] != "finest spacing" and r[f"{a.metric}_error_1"] is not None]
        if errs:
            print(f"\nmean |error| at dx = {s * 1e3:g} mm over {len(errs)} cases with a reference: {100 * sum(errs) / len(errs):.1f} %", end="")
    print()

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    # tab10 repeats after ten lines; tab20 keeps up to twenty cases apart (the dry-ice bench has 13).
    colours = plt.cm.tab10 if len(cases) <= 10 else plt.cm.tab20
    for i, c in enumerate(cases):
        rows = [r for r in all_rows if r["case"] == c]
        pts = [(r["wall_s"], abs(r[f"{a.metric}_error_1"])) for r in rows
               if r[f"{a.metric}_error_1"] not in (None, 0.0) and r["wall_s"]]
        if not pts:
            continue
        style = "-o" if rows[0]["reference"] != "finest spacing" else "--s"
        ax.plot([x for x, _ in pts], [y for _, y in pts], style, label=c, color=colours(i % colours.N))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel(f"|relative error| of {a.metric}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    ax.set_title("solid: against the reference; dashed: against the finest spacing", fontsize=9)
    fig.tight_layout()
    fig.savefig(f"{a.out}.png", dpi=110)


if __name__ == "__main__":
    main()
