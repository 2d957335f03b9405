#!/usr/bin/env bash
# Stability sweep of the oscillating plate (docs/stability.md): numerics.cfl x generic jitter,
# coarse (dx = 5 mm = H/4), END_TIME (default 0.05 s) of simulated time, one thread each.
# Usage: scripts/stability_sweep.sh [SPHFORGE] [OUT_DIR]   (writes OUT_DIR/stability.csv and .md)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
exe="${1:-$here/build/nocuda/bin/sphforge}"
out="${2:-$here/runs/stability_sweep}"
end_time="${END_TIME:-0.05 s}"
mkdir -p "$out"
csv="$out/stability.csv"
echo "cfl,jitter,exit_code,status,steps,simulated_time_s,diagnosis" > "$csv"
for cfl in 0.2 0.4 0.6 0.8 1.0 1.5 2.0; do
  for jitter in 0 0.1 0.2 0.3; do
    dir="$out/cfl${cfl}_jitter${jitter}"
    set +e
    OMP_NUM_THREADS=1 OMP_WAIT_POLICY=PASSIVE "$exe" run "$here/cases/verification/oscillating_plate.json" \
      --out "$dir" --force --quiet --set "numerics.cfl=$cfl" --set "process.jitter=$jitter" \
      --set "run.end_time=$end_time" --set "run.output_interval=$end_time" 2> "$dir.stderr.txt"
    code=$?
    set -e
    python3 - "$dir" "$cfl" "$jitter" "$code" >> "$csv" <<'PY'
import json, sys
d, cfl, jitter, code = sys.argv[1:]
s = json.load(open(d + "/summary.json"))
diag = s.get("diagnosis", "").replace('"', "'")
print(f'{cfl},{jitter},{code},{s["status"]},{s["steps"]},{s["simulated_time_s"]:.6g},"{diag}"')
PY
  done
done
python3 - "$csv" "$end_time" > "$out/stability.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
jit = sorted({r["jitter"] for r in rows}, key=float)
cfls = sorted({r["cfl"] for r in rows}, key=float)
cell = {(r["cfl"], r["jitter"]): r for r in rows}
print(f"| cfl \\ jitter | " + " | ".join(jit) + " |")
print("| --- |" + " --- |" * len(jit))
for c in cfls:
    out = []
    for j in jit:
        r = cell[(c, j)]
        out.append("ok" if r["exit_code"] == "0" else f'exit {r["exit_code"]} (step {r["steps"]}, t = {float(r["simulated_time_s"]):.3g} s)')
    print(f"| {c} | " + " | ".join(out) + " |")
PY
cat "$out/stability.md"
