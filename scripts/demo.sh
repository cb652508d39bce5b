#!/usr/bin/env bash
# The main job on the bundled example part: install, build, then import, validate and slice
# it, writing SVG previews and a JSON summary of the slices under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
part=examples/parts/flanged_bushing.stl
bin=build/release/apps/maxslice/maxslice
mkdir -p out
"$bin" info "$part"
"$bin" slice "$part" --layer 0.5 --svg out/layers --contact-sheet out/contact_sheet.svg \
  --json out/slices.json
echo "maxslice demo: wrote out/slices.json, out/contact_sheet.svg and out/layers/*.svg"
