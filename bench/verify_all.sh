#!/usr/bin/env bash
# Runs the whole 5-axis job (`maxslice slice` with a table-tilt profile: place, plan, order,
# toolpaths, program, and the independent verifier on the written text) on the planner's
# fixtures and on every part under the shared test data's meshes/ (and the large lattice
# cone; with -s also every STEP file under step/), twice per part: the default search (the
# part as given, other bases when it cannot be built) and `--orient given` (the part as the
# file has it, nothing else), with the same profile. Prints a Markdown table with two rows a
# part, "part" and "part (as given)": the verifier's figures, the finished part's share
# inside the beads and the smallest machining stock, and the job's wall time; then counts.
# Parts are read with --repair (the shared set has open scans); those MANIFEST.md says are
# in other units run a second time with --units. The process column says which of the
# profile's processes the program uses: main, or finer N (decision 0019). A part the profile's
# plate cannot hold (the job refuses it before planning) runs once more on the large cell's
# profile, in rows labelled "[large cell]" (decision 0034).
#
#   bench/verify_all.sh [-b MAXSLICE] [-x EXPORT_FIXTURES] [-p PROFILE] [-l LARGE_PROFILE]
#                       [-d TESTDATA_DIR] [-s]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
maxslice=$repo/build/release/apps/maxslice/maxslice
export_fixtures=""
profile=$repo/examples/profiles/reference_5axis_ac.toml
large=$repo/examples/profiles/large_5axis_ac.toml
data=${MAXSLICE_TESTDATA_DIR:-$repo/../shared/testdata}
step=0
while [ $# -gt 0 ]; do
    case $1 in
        -b) maxslice=${2:?}; shift 2 ;;
        -x) export_fixtures=${2:?}; shift 2 ;;
        -p) profile=${2:?}; shift 2 ;;
        -l) large=${2:?}; shift 2 ;;
        -d) data=${2:?}; shift 2 ;;
        -s) step=1; shift ;;
        -h|--help)
            sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'
            echo
            echo "  -b  the maxslice binary (default build/release/apps/maxslice/maxslice)"
            echo "  -x  the fixture exporter (default: bench/maxslice_export_fixtures of -b's build)"
            echo "  -p  the machine profile (default examples/profiles/reference_5axis_ac.toml)"
            echo "  -l  the profile for parts beyond -p's plate (default examples/profiles/large_5axis_ac.toml)"
            echo "  -d  the shared test data (default \$MAXSLICE_TESTDATA_DIR or ../shared/testdata)"
            echo "  -s  also every STEP file under step/"
            exit 0 ;;
        *) echo "verify_all.sh: unknown option '$1'" >&2; exit 2 ;;
    esac
done
# The exporter is built beside maxslice (MAXSLICE_BUILD_BENCH=ON): build/X/apps/maxslice/maxslice
# -> build/X/bench/maxslice_export_fixtures.
[ -n "$export_fixtures" ] ||
    export_fixtures=$(dirname "$(dirname "$(dirname "$maxslice")")")/bench/maxslice_export_fixtures
for exe in "$maxslice" "$export_fixtures"; do
    [ -x "$exe" ] || {
        echo "verify_all.sh: no $exe (bash scripts/build.sh release, with MAXSLICE_BUILD_BENCH=ON for the exporter)" >&2
        exit 2
    }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$export_fixtures" "$work/fixtures" > /dev/null
# The plate a profile models, in words.
plate_of() {
    if grep -q '^\[machine.substrate\]' "$1"; then
        echo "substrate $(awk '/^\[machine.substrate\]/ { on = 1; next } /^\[/ { on = 0 }
            on && /^(size_x_mm|size_y_mm|thickness_mm)/ { v[$1] = $3 }
            END { printf "%s x %s x %s mm", v["size_x_mm"], v["size_y_mm"], v["thickness_mm"] }' "$1") (the verifier checks the head against it)"
    else
        echo "no [machine.substrate]: the head is only warned of below the plate's level (note column)"
    fi
}

echo "# maxslice 5-axis job with the verifier  ($(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown))"
echo
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); profile: ${profile#"$repo/"}, $(plate_of "$profile"); parts read with --repair"
echo
echo "[large cell] rows: parts beyond that plate, on ${large#"$repo/"}, $(plate_of "$large")"
echo
echo "| part | exit | base | process | regions | layers (tilted) | collisions / unsupported / limit | < clearance | coverage % | excess % | finished % | stock mm | build time min | job wall s | note |"
echo "|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
# The units MANIFEST.md states for parts not in millimetres.
stated_units() {
    case ${1##*/} in
        bunny.bin.stl) echo m ;;
        angle_block.STL | featuretype.STL | idler_riser.STL) echo in ;;
    esac
}

# One job: run_job PROFILE FILE LABEL ORIENT [EXTRA ...]; prints the table row and appends a
# tab-separated record (label, exit, verified clean, coverage, excess, finished, wall) to
# $work/rows for the counts.
run_job() {
    local job_profile=$1 f=$2 label=$3 orient=$4
    shift 4
    local args=("$@")
    [ "$orient" = given ] && args+=(--orient given)
    local t0 t1 rc=0 wall note="" vs below
    t0=$EPOCHREALTIME
    "$maxslice" slice "$f" --repair "${args[@]}" --profile "$job_profile" -o "$work/p.gm" --timings \
        > "$work/out" 2> "$work/err" || rc=$?
    t1=$EPOCHREALTIME
    wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
    if [ "$rc" != 0 ]; then
        note=$(grep -m1 "error" "$work/err" | sed 's/^maxslice: error: [^:]*: //; s/|/\\|/g' | cut -c1-150)
    fi
    # How far the head reaches below the plate's level (the job's warning; profiles without
    # [machine.substrate], decision 0016).
    below=$(sed -n "s/.*the head reaches up to \([0-9.]*\) mm below the plate's level.*/\1/p" "$work/err" | head -1)
    [ -z "$below" ] || note="${note:+$note; }head ${below} mm below the plate's level"
    # A written program: the job's summary (stdout). A refused one: the verifier's report and
    # the error line (stderr), when the verifier is what refused it.
    local src=$work/out
    [ "$rc" = 0 ] || src=$work/err
    awk -v label="$label" -v rc="$rc" -v wall="$wall" -v note="$note" -v rows="$work/rows" '
        function num(s) { return s + 0 }
        /^process/ { proc = $2 " " $3; sub(/:/, "", proc) }
        /^orientation/ {
            base = $0; sub(/^orientation +along /, "", base)
            if (base ~ /^\(/) { base = (match(base, /flat face [0-9]+/) ? "face " substr(base, RSTART + 10, RLENGTH - 10) : "other") }
            else sub(/ .*/, "", base)
        }
        /^regions/ { regions = $2; layers = $5; tilted = $7; sub(/\(/, "", tilted) }
        /^verified|verifier refused the program/ {
            if (match($0, /[0-9]+ collisions/)) col = num(substr($0, RSTART, RLENGTH))
            if (match($0, /[0-9]+ unsupported beads/)) uns = num(substr($0, RSTART, RLENGTH))
            if (match($0, /[0-9]+ (axis-)?limit violations/)) lim = num(substr($0, RSTART, RLENGTH))
            if (match($0, /[0-9]+ closer than/)) clr = num(substr($0, RSTART, RLENGTH))
        }
        /^coverage/ {
            cov = $2; sub(/%.*/, "", cov)
            if ($0 ~ /excess/) { exc = $NF; sub(/%.*/, "", exc) }
        }
        /^excess/ { exc = $2; sub(/%.*/, "", exc) }
        /^finished part/ && $3 ~ /%$/ {
            fin = $3; sub(/%/, "", fin)
            if (match($0, /smallest stock -?[0-9.]+/)) stock = substr($0, RSTART + 15, RLENGTH - 15)
        }
        /^build time/ { bt = $3 }
        END {
            written = (rc == 0)
            checks = (col != "") ? col " / " uns " / " lim : "-"
            printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", label, rc,
                written ? (base ? base : "given") : "-", written ? (proc ? proc : "main") : "-",
                regions != "" ? regions : "-", layers != "" ? layers " (" tilted ")" : "-",
                checks, clr != "" ? clr : "-", cov != "" ? cov : "-", exc != "" ? exc : "-",
                fin != "" ? fin : "-", stock != "" ? stock : "-", bt && written ? bt : "-", wall, note
            clean = written && col == 0 && uns == 0 && lim == 0 && clr == 0
            printf "%s\t%s\t%d\t%s\t%s\t%s\t%s\n", label, rc, clean, cov, exc, fin, wall >> rows
        }' "$src"
}

{
    ls "$work"/fixtures/*.stl
    find "$data/meshes" -type f | sort | while read -r f; do
        echo "$f"
        u=$(stated_units "$f")
        [ -z "$u" ] || printf '%s\t%s\n' "$f" "$u"
    done
    echo "$data/large/Spiral_lattice_cone_2_occt.stl"
    [ "$step" = 0 ] || find "$data/step" -type f | sort
} | while IFS=$'\t' read -r f units; do
    [ -f "$f" ] || continue
    case $f in "$work"/*) rel="fixture ${f##*/}"; rel=${rel%.stl} ;; *) rel=${f#"$data/"} ;; esac
    extra=()
    if [ -n "$units" ]; then
        extra=(--units "$units")
        rel="$rel --units $units"
    fi
    for orient in search given; do
        label=$rel
        [ "$orient" = search ] || label="$rel (as given)"
        run_job "$profile" "$f" "$label" "$orient" "${extra[@]}"
        # Refused before planning because the part's footprint reaches beyond the plate
        # (pipeline::check_fits_machine): the large cell's plate may hold it. The job's own
        # refusal, not a base the search tried and refused for that ("other orientations
        # tried: ...").
        if grep -qE "^maxslice: error: [^ ]+: the part's footprint on the plate" "$work/err"; then
            run_job "$large" "$f" "${label/#"$rel"/"$rel [large cell]"}" "$orient" "${extra[@]}"
        fi
    done
done

# The counts under the table: per run, the programs written, those that verify clean, those
# that meet 97 % coverage with under 5 % excess and those whose finished part is at least
# 99.5 % inside the beads; the fixtures that build; the wall time and the slowest job.
echo
awk -F'\t' '
    { given = ($1 ~ / \(as given\)$/); large = ($1 ~ / \[large cell\]/)
      k = (large ? "L" : "") (given ? "g" : "s"); part = $1; sub(/ \(as given\)$/, "", part)
      n[k]++; if ($2 == 0) { w[k]++; c[k] += $3; if ($4 >= 97 && $5 < 5) m[k]++; if ($6 != "" && $6 >= 99.5) f[k]++ }
      if (part ~ /^fixture /) { fx[k]++; if ($2 == 0) fb[k]++ }
      wall[k] += $7; if ($7 > slow) { slow = $7; slowest = $1 } }
    function line(k, what) {
        printf "- %s: %d of %d rows write a program (%d refused); %d of %d verify with 0 collisions, 0 unsupported beads, 0 limit violations and none closer than the clearance; %d reach 97 %% coverage with under 5 %% excess; %d have the finished part at least 99.5 %% inside beads; %swall time %.1f s.\n",
            what, w[k], n[k], n[k] - w[k], c[k], w[k], m[k], f[k],
            fx[k] ? sprintf("%d of %d fixtures build; ", fb[k], fx[k]) : "", wall[k]
    }
    END {
        line("s", "default search")
        line("g", "as given (--orient given)")
        if (n["Ls"] + n["Lg"] > 0) {
            line("Ls", "default search, [large cell] rows")
            line("Lg", "as given, [large cell] rows")
        }
        printf "- slowest job: %s (%.2f s).\n", slowest, slow
    }' "$work/rows"
