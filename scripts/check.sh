#!/usr/bin/env bash
# The whole test suite: install, build (warnings as errors), run every test, then run the
# suite again under AddressSanitizer + UndefinedBehaviorSanitizer (all but the three sweeps
# over every shared model and the slow whole-part plans (PlanCliSlow), which only repeat the
# release run's coverage at 3x the time; the CLI sweep over every malformed file does run
# under the sanitizers).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release -DMAXSLICE_WERROR=ON
ctest --preset release
bash scripts/build.sh asan -DMAXSLICE_WERROR=ON
ctest --preset asan -E "Manifest\.|EverySharedModel|EverySharedMesh|PlanCliSlow\."
