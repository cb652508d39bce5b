#!/usr/bin/env bash
# The main job on the bundled example parts: install, build, then import, validate, slice and
# plan them, writing the deposition programs (GM code for the reference LMD cell and LinuxCNC
# G-code; a 5-axis GM program for the reference cell's A/C table on the bearing seat, whose
# boss must be built sideways), each replayed by the independent verifier before it is
# written, per-layer SVG previews of the tracks and a JSON summary of the slices under out/.
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
# A part with an overhang no planar build holds, kept as it stands (as material added to a
# part on the table would be): planned (3 regions, the boss built sideways), ordered, written
# for the A/C table machine and verified; then verified again on its own. (Without
# --orient given, the search stands it on its end instead: one planar region.)
seat=examples/parts/bearing_seat.stl
"$bin" slice "$seat" --profile examples/profiles/reference_5axis_ac.toml --orient given \
  -o out/bearing_seat_5axis.gm
"$bin" plan "$seat" --profile examples/profiles/reference_5axis_ac.toml --orient given \
  --plan out/bearing_seat_plan.json --order-out out/bearing_seat_order.ply
"$bin" verify out/bearing_seat_5axis.gm --model "$seat" \
  --profile examples/profiles/reference_5axis_ac.toml --json out/bearing_seat_verify.json
echo "maxslice demo: wrote out/flanged_bushing.gm, out/flanged_bushing.ngc, out/slices.json,"
echo "  out/contact_sheet.svg and out/layers/*.svg (tracks in blue, idle moves dashed red),"
echo "  out/plan.json, out/plan/*.svg and out/plan_order.ply (the plan and its build order),"
echo "  out/bearing_seat_5axis.gm (5-axis, A/C table), its plan, build order and verifier report"
