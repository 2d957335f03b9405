#!/usr/bin/env bash
# First run on a fresh Debian 12 machine: installs the dependencies, builds the `release` preset and
# runs the default case (paste_orifice_quick: a coarse paste ram extrusion through an orifice) into a
# new, time-stamped folder under runs/, so earlier output is never touched. Extra arguments go to
# `sphforge run` (e.g. --set KEY=VALUE, --quiet).
# Works from any directory.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$(pwd)

scripts/install-deps.sh
cmake --preset release
cmake --build --preset release

out="runs/paste_orifice_quick-$(date +%Y%m%d-%H%M%S)"
mkdir -p runs
build/release/bin/sphforge run --out "$out" "$@"

cat <<MSG

sphforge: done. Output in ${root}/${out}
  summary.json   case, status, particle/step counts, wall time, process metrics
  history.csv    one row per history interval (forces, probes, energies; units in the column names)
  particles.pvd  particle fields over time      tools.pvd  rigid tool surfaces over time

Open it in ParaView:
  paraview ${root}/${out}/particles.pvd
  In ParaView: Apply, set the representation to "Points" (or "Point Gaussian" for round
  particles) and colour by any field; add the tools with File > Open > tools.pvd, Apply.
MSG
