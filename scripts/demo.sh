#!/usr/bin/env bash
# The main job on the bundled example part: install, build, then import, validate, slice and
# plan it, writing the deposition program (GM code for the reference LMD cell and LinuxCNC
# G-code), per-layer SVG previews of the tracks and a JSON summary of the slices under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
part=examples/parts/flanged_bushing.stl
bin=build/release/apps/maxslice/maxslice
mkdir -p out
"$bin" info "$part"
"$bin" slice "$part" --profile examples/profiles/reference_lmd.toml -o out/flanged_bushing.gm \
  --svg out/layers --contact-sheet out/contact_sheet.svg --json out/slices.json
"$bin" slice "$part" --profile examples/profiles/linuxcnc_generic.toml \
  -o out/flanged_bushing.ngc
# The multi-axis plan and its collision-checked build order (one region for this part).
"$bin" plan "$part" --plan out/plan.json --svg out/plan --order-out out/plan_order.ply
echo "maxslice demo: wrote out/flanged_bushing.gm, out/flanged_bushing.ngc, out/slices.json,"
echo "  out/contact_sheet.svg and out/layers/*.svg (tracks in blue, idle moves dashed red),"
echo "  out/plan.json, out/plan/*.svg and out/plan_order.ply (the plan and its build order)"
