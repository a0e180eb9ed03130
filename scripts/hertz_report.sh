#!/usr/bin/env bash
# Regenerates the Hertz report material of doc/verification.md: the decks of input/hertz/
# (hertz_cases.py), all runs (paper cases, refinement series, static) into results/hertz-suite,
# the table verification/hertz/results_table.md and the figures doc/figures/hertz_*.png.
#   scripts/hertz_report.sh [path to ictus]      (default build/bin/ictus; about 1 minute)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
ictus=${1:-$here/build/bin/ictus}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
/usr/bin/python3 "$here/verification/hertz/hertz_cases.py"
/usr/bin/python3 "$here/scripts/hertz_suite.py" --ictus "$ictus" --out "$here/results/hertz-suite" \
  --groups paper series static --table "$here/verification/hertz/results_table.md" \
  --figures "$here/doc/figures"
