#!/usr/bin/env bash
# Runs `maxslice plan` on every part under the shared test data's meshes/ (and the large
# lattice cone) and prints a Markdown table: regions, splits, tilts wanted, layers, plan
# volume against the mesh's, planning time (the planner's own), the build order (complete or
# the number of conflicts, jumps against the fewest possible, sections, smallest margin, the
# ordering's own time) and the whole process's wall time. Parts are read with --repair (the
# shared set has open scans).
#
#   bench/plan_all.sh [-b MAXSLICE] [-d TESTDATA_DIR] [-- EXTRA PLAN OPTIONS]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
maxslice=$repo/build/release/apps/maxslice/maxslice
data=${MAXSLICE_TESTDATA_DIR:-$repo/../shared/testdata}
while [ $# -gt 0 ]; do
    case $1 in
        -b) maxslice=${2:?}; shift 2 ;;
        -d) data=${2:?}; shift 2 ;;
        --) shift; break ;;
        -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "plan_all.sh: unknown option '$1'" >&2; exit 2 ;;
    esac
done
[ -x "$maxslice" ] || { echo "plan_all.sh: no maxslice at $maxslice (bash scripts/build.sh release)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "# maxslice plan on the shared parts  ($(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown))"
echo
echo "machine: $(nproc) cores; options: --repair $*; default profile (2.5 mm track, 0.5 mm layers, phi_self 20 deg, alpha 30, beta 60)"
echo
echo "| part | triangles | exit | regions | splits | tilts wanted | layers | unsupported layers | plan / mesh volume | planning s | order | jumps (min) | sections | smallest margin mm | ordering s | wall s |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|"
{ find "$data/meshes" -type f | sort; echo "$data/large/Spiral_lattice_cone_2_occt.stl"; } | while read -r f; do
    [ -f "$f" ] || continue
    rel=${f#"$data/"}
    tris=$("$maxslice" info "$f" --repair 2>/dev/null | awk '/^triangles/ { print $2; exit }' || true)
    t0=$EPOCHREALTIME
    rc=0
    "$maxslice" plan "$f" --repair "$@" > "$work/out" 2> "$work/err" || rc=$?
    t1=$EPOCHREALTIME
    wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
    if ! grep -q "^build order" "$work/out"; then
        msg=$(grep -m1 "error" "$work/err" | sed 's/|/\\|/g' | cut -c1-120)
        echo "| $rel | ${tris:--} | $rc | - | - | - | - | - | $msg | - | - | - | - | - | - | $wall |"
        continue
    fi
    awk -v rel="$rel" -v tris="${tris:--}" -v wall="$wall" -v rc="$rc" '
        /^regions/ { regions = $2 }
        /^splits/ { splits = $2 }
        /^tilts wanted/ { tilts = $3 }
        /^layers/ { layers = $2 }
        /^unsupported/ { uns = $2 }
        /^plan volume/ { vol = ($0 ~ /not closed/) ? "open mesh" : $NF; sub(/\)$/, "", vol) }
        /^planning time/ { t = $3 }
        /^build order/ { order = ($0 ~ /NO collision-free/) ? "conflicts" : "complete" }
        /^  conflict:/ { conflicts++ }
        /^jumps/ { jumps = $2; mj = $NF; sub(/\)$/, "", mj) }
        /^sections/ { sections = $2 }
        /^smallest margin/ { margin = ($3 == "none") ? "none in reach" : $3 }
        /^ordering time/ { ot = $3 }
        END {
            if (order == "conflicts") order = conflicts " conflicts"
            printf "| %s | %s | %s | %s | %s | %s | %s | %d | %s | %s | %s | %s (%s) | %s | %s | %s | %s |\n", rel, tris, rc, regions, splits, tilts, layers, uns, vol, t, order, jumps, mj, sections, margin, ot, wall }' "$work/out"
done
