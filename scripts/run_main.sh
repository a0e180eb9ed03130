#!/usr/bin/env bash
# The main job: set-up (packages, configure, build) and the benchmark run.
# Results go to results/ in the repository (override with RESULTS_DIR).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$here/scripts/setup.sh" Release
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out=${RESULTS_DIR:-$here/results}
mkdir -p "$out"
ictus="${BUILD_DIR:-$here/build}/bin/ictus"
# Until contact lands, the main job is the classic-FE wave benchmark of input/bar_wave.
"$ictus" "$here/input/bar_wave/bar_q8.inp" -o "$out/bar_q8.h5"
