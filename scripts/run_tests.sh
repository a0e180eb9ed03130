#!/usr/bin/env bash
# The whole test suite: set-up (packages, configure, build) and then CTest.
#   scripts/run_tests.sh [extra ctest arguments, e.g. -L unit]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$here/scripts/setup.sh" Release
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
cd "${BUILD_DIR:-$here/build}"
ctest --output-on-failure -j "$(nproc)" "$@"
