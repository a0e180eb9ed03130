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
# The dynamic Hertz benchmark (doc/reference.md §1, doc/verification.md): IGA p = 2 and FEA Q8, both
# with HRZ mass, 8 x 8, dt = 5e-4, T = 0.9. Results files, logs, the comparison table and the
# Fig. 3 plot (contact force and maximal pressure against the quasi-static Hertz model) go to
# $out/hertz; the table is printed.
/usr/bin/python3 "$here/scripts/hertz_suite.py" --ictus "$ictus" --out "$out/hertz" \
  --groups fig3 --table "$out/hertz/results_table.md" --figures "$out/hertz"
