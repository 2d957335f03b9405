#!/usr/bin/env bash
# Builds sphforge with the `ci` preset (Release; the CUDA backend too when nvcc exists) and runs the
# test suite CI runs: labels unit, integration, verification, cases and stress. Long validation runs
# (label `validation`) are never run here. Extra arguments go to ctest, e.g.
#   scripts/run-tests.sh -L unit          # only the unit tests
#   scripts/run-tests.sh -R Kernels -V    # one group, verbose
# Works from any directory; dependencies are installed first (fast when already present).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

scripts/install-deps.sh
cmake --preset ci
cmake --build --preset ci
ctest --preset ci "$@"
