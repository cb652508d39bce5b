#!/usr/bin/env bash
# The whole test suite: install, build (warnings as errors), run every test, then run the
# suite again in the one sanitizer build (clang-16, AddressSanitizer + UndefinedBehavior-
# Sanitizer: all but the three sweeps over every shared model and the slow whole-part jobs
# (PlanCliSlow, FiveAxisSlow), which only repeat the release run's coverage at 3x the time;
# the CLI sweep over every malformed file does run under the sanitizers), then every
# libFuzzer harness of that build for 60 s on a copy of its corpus (fuzz/corpus,
# docs/fuzzing.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release -DMAXSLICE_WERROR=ON
ctest --preset release
bash scripts/build.sh asan -DMAXSLICE_WERROR=ON
ctest --preset asan -E "Manifest[./]|EverySharedModel|EverySharedMesh|PlanCliSlow\.|FiveAxisSlow\.|BuildOrderSlow\."
bash fuzz/run.sh -b build/asan -t "${MAXSLICE_FUZZ_SECONDS:-60}" -j 2
