#!/usr/bin/env bash
# Runs the whole table-tilt job as given (`maxslice slice --orient given --finer off`) on every
# planner fixture as drawn and turned about Z by each ANGLE (through the middle of its box,
# maxslice_export_fixtures DIR ANGLE) and prints a Markdown table of exit codes and region
# counts: turning a part about Z changes neither the head's reach nor the plate under it, so
# a fixture should keep both (issue 24; decision 0041). The last line counts those that do.
#
#   bench/turned_fixtures.sh [-b MAXSLICE] [-x EXPORT_FIXTURES] [-p PROFILE] [ANGLE ...]
#   (default angles: 37 113 200 247)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
maxslice=$repo/build/release/apps/maxslice/maxslice
export_fixtures=""
profile=$repo/examples/profiles/reference_5axis_ac.toml
while [ $# -gt 0 ]; do
    case $1 in
        -b) maxslice=${2:?}; shift 2 ;;
        -x) export_fixtures=${2:?}; shift 2 ;;
        -p) profile=${2:?}; shift 2 ;;
        -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        -*) echo "turned_fixtures.sh: unknown option '$1'" >&2; exit 2 ;;
        *) break ;;
    esac
done
angles=("$@")
[ ${#angles[@]} -gt 0 ] || angles=(37 113 200 247)
# -> build/X/bench/maxslice_export_fixtures.
[ -n "$export_fixtures" ] ||
    export_fixtures=$(dirname "$(dirname "$(dirname "$maxslice")")")/bench/maxslice_export_fixtures
for exe in "$maxslice" "$export_fixtures"; do
    [ -x "$exe" ] || { echo "turned_fixtures.sh: no executable at $exe (bash scripts/build.sh release)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# "exit/regions" of the job on one part.
job() {
    local rc=0 regions
    "$maxslice" slice "$1" --profile "$profile" --orient given --finer off -o "${1%.stl}.gm" \
        > "$work/out" 2> "$work/err" || rc=$?
    regions=$(awk '/^regions/ { print $2; exit }' "$work/out")
    echo "$rc/${regions:--}"
}

echo "# maxslice fixtures turned about Z  ($(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown))"
echo
echo "profile: ${profile#"$repo/"}; each cell: exit code / regions (--orient given --finer off)"
echo
header="| fixture | as drawn |"
rule="|---|---:|"
for a in "${angles[@]}"; do
    header="$header $a deg |"
    rule="$rule---:|"
done
echo "$header same |"
echo "$rule---|"
"$export_fixtures" "$work/0" > /dev/null
for a in "${angles[@]}"; do "$export_fixtures" "$work/$a" "$a" > /dev/null; done
kept=0
total=0
for f in "$work"/0/*.stl; do
    name=$(basename "$f" .stl)
    drawn=$(job "$f")
    row="| $name | $drawn |"
    same=yes
    for a in "${angles[@]}"; do
        other=$(job "$work/$a/$name.stl")
        row="$row $other |"
        [ "$other" = "$drawn" ] || same=no
    done
    echo "$row $same |"
    total=$((total + 1))
    [ "$same" = no ] || kept=$((kept + 1))
done
echo
echo "- $kept of $total fixtures keep their exit code and region count at every angle (${angles[*]} degrees)."
