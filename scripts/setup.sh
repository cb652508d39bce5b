#!/usr/bin/env bash
# Installs what maxslice needs from Debian 12's archive, only the packages that are missing.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config clang-format python3
  libpolyclipping-dev libeigen3-dev libtbb-dev libfmt-dev libcli11-dev nlohmann-json3-dev
  libtomlplusplus-dev libassimp-dev lib3mf-dev libboost-dev
  libopenvdb-dev    # distance fields for the near-net shape (src/nearnet/, decision 0025)
  libminizip-dev    # the 3MF expansion check reads the model parts (src/io/threemf_prescan.cpp)
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libmimalloc-dev   # the allocator of the maxslice program (docs/decisions/0018-allocator.md)
  linuxcnc-uspace   # its standalone interpreter rs274 checks our linuxcnc programs in the tests
  clang-16 libclang-rt-16-dev  # the sanitizer + libFuzzer build (docs/fuzzing.md)
  ccache            # carries builds between runs (docs/decisions/0020-sanitizer-fuzz-build.md)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "maxslice setup: installing ${missing[*]}"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
