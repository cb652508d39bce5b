#!/usr/bin/env bash
# Configures and builds one CMake preset: release (default), debug or asan (clang-16 with
# AddressSanitizer + UndefinedBehaviorSanitizer, and the libFuzzer harnesses).
# With ccache installed, compilations go through it. The cache lives outside the clone
# (CCACHE_DIR, default ~/.cache/ccache) and paths are hashed relative to the clone
# (CCACHE_BASEDIR, CCACHE_NOHASHDIR), so a fresh clone in another folder reuses the objects
# of an earlier run (docs/decisions/0020-sanitizer-fuzz-build.md).
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
shift || true
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$PWD"
  export CCACHE_NOHASHDIR=1
  ccache --max-size="${MAXSLICE_CCACHE_SIZE:-5G}" >/dev/null
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake --preset "$preset" "${launcher[@]}" "$@" >/dev/null
cmake --build --preset "$preset"
