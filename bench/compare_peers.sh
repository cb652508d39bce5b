#!/usr/bin/env bash
# Times maxslice and the peer slicers (PrusaSlicer, CuraEngine, Slic3r) in one run, on the
# same models and layer heights, with matched settings, and checks the speed targets of the
# "foundation" (slicing) and "part in, program out" (whole job) issues.
#
#   bench/compare_peers.sh [options]
#
#   -r, --runs N          timed runs per measurement, median reported (default 3; one
#                         unrecorded warm-up run comes first, so the page cache is warm)
#   -m, --models LIST     comma-separated: lattice, bunny, bunny1m, torus2m or STL paths
#                         (default lattice,bunny,torus2m)
#   -l, --layers LIST     layer heights in mm, comma-separated (default 0.2,0.5)
#   -p, --peers LIST      prusa,cura,slic3r or none (default all three)
#   -b, --maxslice PATH   the maxslice binary (default build/release/apps/maxslice/maxslice,
#                         built with scripts/build.sh release, or cmake, when missing)
#   -t, --threads N       maxslice --threads (default 0 = all cores; the peers use both)
#   -d, --models-dir DIR  where the generated models live (default build/bench-models,
#                         git-ignored); bunny150/bunny1m/torus2m are made there if missing
#   -P, --peers-dir DIR   the peer scripts (default /work/shared/peers, or $MAXSLICE_PEERS_DIR)
#       --no-whole        skip the peers' whole-process timings (stages only; saves ~2/3)
#       --wait-idle S     before each measurement wait up to S seconds for the rest of the
#                         machine to use < 0.25 core (default 0: do not wait, only report)
#       --tsv FILE        also write every median as a TSV row to FILE
#   -h, --help
#
# The peers come from /work/shared/peers/install.sh DIR (run as root: apt-get installs
# prusa-slicer, cura-engine, slic3r and GNU time; it also makes the models). CuraEngine
# needs CURA_DEFS (default DIR/cura_defs).
#
# What is measured (all with a warm page cache: every file was read by the warm-up run):
#   whole job      mesh in, program out: wall seconds (bash $EPOCHREALTIME around GNU time),
#                  CPU seconds (user + system, GNU time) and peak RSS (GNU time %M) of
#                  `maxslice slice MODEL --layer L -o OUT.ngc` and of the peers' slice_*.sh,
#                  all with matched settings: one contour, rectilinear/zigzag 100% fill, the
#                  same layer height and bead width (BEAD_WIDTH of the peers' common.sh,
#                  1.0 mm), no supports; maxslice gets a profile written from those values
#                  (overlap 0, so its fill pitch is the bead width as the peers' is).
#   stages         maxslice: its own --timings of that same run (load = read + weld,
#                  validate, slice, paths = toolpaths + move list, write = program text);
#                  PrusaSlicer and CuraEngine: load and slice from their own logs
#                  (stages.py); Slic3r has no stage log: its --export-svg run (start-up,
#                  load and slicing, no toolpaths) is the closest it has to a slice stage.
#   plain read     `cat FILE > /dev/null` (wall, includes starting cat, ~1 ms).
#   cold read      the same after `dd iflag=nocache count=0` dropped the file's cached pages
#                  (reported beside target (c), which is measured against the warm read).
#   foreign load   /proc/stat busy time of the whole machine during a run minus the run's
#                  own CPU time, divided by its wall time: cores used by other work. Wall
#                  times with a foreign load above ~0.2 core are inflated; CPU seconds less.
# Targets (per model and layer height):
#   (a) maxslice load (read + weld) >= 3x faster than CuraEngine's load stage
#   (b) maxslice slice stage faster than CuraEngine's slice stage
#   (c) maxslice slice stage <= 2x the plain read time of the file
#   (d) maxslice whole job faster than every peer's whole job
#   (e) on the largest model (most triangles): maxslice whole job >= 3x faster than the
#       fastest peer's
# When maxslice refuses a model (e.g. an open mesh, which the peers repair silently), it is
# timed again with --repair, and those stages are used (marked "with --repair").
set -euo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
runs=3
models_arg=lattice,bunny,torus2m
layers_arg=0.2,0.5
peers_arg=prusa,cura,slic3r
maxslice=$repo/build/release/apps/maxslice/maxslice
threads=0
models_dir=$repo/build/bench-models
peers_dir=${MAXSLICE_PEERS_DIR:-/work/shared/peers}
whole=1
wait_idle=0
tsv=

usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
die() { echo "compare_peers.sh: $*" >&2; exit 2; }

while [ $# -gt 0 ]; do
    case $1 in
        -r|--runs) runs=${2:?}; shift 2 ;;
        -m|--models) models_arg=${2:?}; shift 2 ;;
        -l|--layers) layers_arg=${2:?}; shift 2 ;;
        -p|--peers) peers_arg=${2:?}; shift 2 ;;
        -b|--maxslice) maxslice=${2:?}; shift 2 ;;
        -t|--threads) threads=${2:?}; shift 2 ;;
        -d|--models-dir) models_dir=${2:?}; shift 2 ;;
        -P|--peers-dir) peers_dir=${2:?}; shift 2 ;;
        --no-whole) whole=0; shift ;;
        --wait-idle) wait_idle=${2:?}; shift 2 ;;
        --tsv) tsv=${2:?}; shift 2 ;;
        -h|--help) usage; exit 0 ;;
        *) die "unknown option '$1' (see --help)" ;;
    esac
done
[[ $runs =~ ^[1-9][0-9]*$ ]] || die "--runs must be a positive integer"
[[ $threads =~ ^[0-9]+$ ]] || die "--threads must be a non-negative integer"
IFS=', ' read -r -a model_names <<< "$models_arg"
IFS=', ' read -r -a layers <<< "$layers_arg"
IFS=', ' read -r -a peers <<< "$peers_arg"
[ "${peers[*]}" = none ] && peers=()
for p in "${peers[@]}"; do
    case $p in prusa|cura|slic3r) ;; *) die "unknown peer '$p' (prusa, cura, slic3r)" ;; esac
done

gnu_time=/usr/bin/time
[ -x "$gnu_time" ] || die "GNU time not found (Debian package 'time')"
mkdir -p "$models_dir"
models_dir=$(cd "$models_dir" && pwd)
export CURA_DEFS=${CURA_DEFS:-$models_dir/cura_defs}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The peers' bead width (their common.sh, overridable from the environment as there).
bead=${BEAD_WIDTH:-$(bash -c "source '$peers_dir/common.sh' 2>/dev/null; echo \${BEAD_WIDTH:-1.0}")}
bed=${BED:-1000}
# A machine and process profile matching the peers' settings (docs/profiles.md): a bed of
# BED x BED x BED mm with the part in the middle, one contour, fill pitch = bead width.
matched_profile() {         # matched_profile LAYER > FILE
    awk -v w="$bead" -v l="$1" -v bed="$bed" 'BEGIN {
        hmax = (l > w) ? l : w; hmin = l / 4
        printf "[machine]\nname = \"bench: matched to the peer slicers\"\nkinematics = \"xyz\"\n"
        printf "dialect = \"linuxcnc\"\nfeed_min_mm_min = 1.0\nfeed_max_mm_min = 20000.0\n"
        printf "laser_power_min_w = 0.0\nlaser_power_max_w = 1000.0\npowder_feed_max_g_min = 30.0\n"
        printf "[machine.axes]\nX = { min = 0.0, max = %g }\nY = { min = 0.0, max = %g }\n", bed, bed
        printf "Z = { min = -1.0, max = %g }\n", bed
        printf "[machine.codes]\nlaser_on = \"M3 S700\"\nlaser_off = \"M5\"\n"
        printf "powder_on = \"M7\"\npowder_off = \"M9\"\n"
        printf "[process]\ntrack_width_mm = %g\nlayer_height_mm = %g\n", w, l
        printf "h_min_mm = %g\nh_max_mm = %g\noverlap = 0.0\ncontour_passes = 1\n", hmin, hmax
        printf "laser_power_w = 700.0\nlaser_power_off_w = 0.0\npowder_feed_g_min = 8.0\n"
        printf "deposition_feed_mm_min = 381.0\ntravel_feed_mm_min = 2540.0\n"
        printf "dwell_after_laser_on_ms = 0.0\nself_supporting_angle_deg = 20.0\n"
    }'
}

# ---------------------------------------------------------------- the maxslice binary
if [ ! -x "$maxslice" ]; then
    echo "compare_peers.sh: $maxslice missing, building it" >&2
    if [ -f "$repo/scripts/build.sh" ] && bash "$repo/scripts/build.sh" release >&2; then :
    else
        cmake -S "$repo" -B "$repo/build/release" -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
        cmake --build "$repo/build/release" --target maxslice >&2
    fi
fi
[ -x "$maxslice" ] || die "no maxslice binary at $maxslice"

# ---------------------------------------------------------------- peers available?
have_peer() {
    case $1 in
        prusa) type -P prusa-slicer >/dev/null ;;
        cura) type -P CuraEngine >/dev/null && [ -f "$CURA_DEFS/fdmprinter.def.json" ] ;;
        slic3r) type -P slic3r >/dev/null ;;
    esac
}
active_peers=()
for p in "${peers[@]}"; do
    if have_peer "$p"; then active_peers+=("$p")
    else echo "compare_peers.sh: peer '$p' not installed (run $peers_dir/install.sh $models_dir as root); skipped" >&2
    fi
done
peers=("${active_peers[@]}")

# ---------------------------------------------------------------- models
mk() { python3 "$peers_dir/make_big_mesh.py" "$@" >&2; }
model_path() {              # name or path -> path, making the generated models if missing
    local f
    case $1 in
        lattice) echo /work/shared/testdata/large/Spiral_lattice_cone_2_occt.stl; return ;;
        bunny) f=$models_dir/bunny150.stl ;;
        bunny1m) f=$models_dir/bunny1m.stl ;;
        torus2m) f=$models_dir/torus2m.stl ;;
        *) [ -f "$1" ] || die "no model '$1'"; echo "$1"; return ;;
    esac
    if [ ! -f "$f" ]; then
        local src=$models_dir/stl-models/objects/bunny.bin.stl
        case $1 in
            torus2m) mk torus "$f" --nu 1000 --nv 1000 ;;
            bunny|bunny1m)
                [ -f "$src" ] || die "$src missing: run $peers_dir/install.sh $models_dir"
                [ -f "$models_dir/bunny150.stl" ] ||
                    mk transform "$src" "$models_dir/bunny150.stl" --scale 1000 --yup --sink 7
                [ "$1" = bunny1m ] && mk subdivide "$models_dir/bunny150.stl" "$f" --levels 2 ;;
        esac
    fi
    echo "$f"
}

# ---------------------------------------------------------------- measuring
busy_jiffies() { awk '/^cpu / { print $2 + $3 + $4 + $7 + $8 + $9; exit }' /proc/stat; }
median() { sort -g | awk '{ a[NR] = $1 } END { if (NR == 0) print "nan"; else print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }
hz=$(getconf CLK_TCK)
# time_reads FILE warm|cold: median wall seconds of `cat FILE > /dev/null` over read_runs runs,
# each after dropping the file's cached pages when cold.
read_runs=$((runs > 5 ? runs : 5))
time_reads() {
    local i t0 t1
    for i in $(seq 1 "$read_runs"); do
        [ "$2" = cold ] && { dd if="$1" iflag=nocache count=0 status=none 2>/dev/null || true; }
        t0=$EPOCHREALTIME; cat "$1" > /dev/null; t1=$EPOCHREALTIME
        awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.5f\n", b - a }'
    done | median
}

# Cores used by everything else over `secs` seconds, while we do nothing.
idle_sample() {
    local b0 b1
    b0=$(busy_jiffies); sleep "$1"; b1=$(busy_jiffies)
    awk -v d=$((b1 - b0)) -v hz="$hz" -v s="$1" 'BEGIN { printf "%.2f", d / hz / s }'
}
wait_for_idle() {
    [ "$wait_idle" = 0 ] && return 0
    local deadline=$((SECONDS + wait_idle)) load
    while :; do
        load=$(idle_sample 2)
        awk -v l="$load" 'BEGIN { exit !(l < 0.25) }' && return 0
        if [ $SECONDS -ge $deadline ]; then
            echo "compare_peers.sh: machine still busy ($load cores) after ${wait_idle}s; measuring anyway" >&2
            return 0
        fi
        echo "compare_peers.sh: waiting for the machine to be idle ($load cores busy)" >&2
        sleep 3
    done
}

# measure KEY CMD... : 1 warm-up + $runs timed runs. Leaves per-run rows in $work/KEY.runs
# (wall user sys maxrss_kib exit foreign_cores) and each run's stderr in $work/KEY.errN.
measure() {
    local key=$1; shift
    local i t0 t1 b0 b1 rc
    wait_for_idle
    : > "$work/$key.runs"
    for i in $(seq 0 "$runs"); do
        rc=0
        b0=$(busy_jiffies); t0=$EPOCHREALTIME
        "$gnu_time" -o "$work/time.out" -f '%U %S %M' "$@" >/dev/null 2>"$work/$key.err$i" || rc=$?
        t1=$EPOCHREALTIME; b1=$(busy_jiffies)
        [ "$i" -eq 0 ] && continue
        awk -v t0="$t0" -v t1="$t1" -v b="$((b1 - b0))" -v hz="$hz" -v rc="$rc" '
            END { wall = t1 - t0; own = $1 + $2
                  foreign = (b / hz - own) / wall; if (foreign < 0) foreign = 0
                  printf "%.4f %.2f %.2f %d %d %.2f\n", wall, $1, $2, $3, rc, foreign }' \
            "$work/time.out" >> "$work/$key.runs"
    done
}
col() { awk -v c="$2" '{ print $c }' "$work/$1.runs" | median; }
cpu_med() { awk '{ print $2 + $3 }' "$work/$1.runs" | median; }
rss_med() { awk '{ print $4 / 1024 }' "$work/$1.runs" | median; }
max_foreign() { awk 'BEGIN { m = 0 } $6 > m { m = $6 } END { printf "%.2f", m }' "$work/$1.runs"; }
exits() { awk '{ print $5 }' "$work/$1.runs" | sort -u | paste -sd, -; }
# Median of a "timing NAME S" line over the timed runs' stderr.
ms_stage() {
    local key=$1 name=$2 i
    for i in $(seq 1 "$runs"); do
        awk -v n="$name" '$1 == "timing" && $2 == n { print $3 }' "$work/$key.err$i"
    done | median
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "" || b == "" || a == "nan" || b == "nan" || b + 0 == 0) print "-"; else printf "%.2f", a / b }'; }
num() { awk -v a="$1" -v p="${2:-3}" 'BEGIN { if (a == "" || a == "nan") print "-"; else printf "%.*f", p, a }'; }

declare -A R              # results: R[model|layer|what] = value
ms_stages=(load validate slice paths write)
emit_tsv() { [ -n "$tsv" ] && printf '%s\n' "$(IFS=$'\t'; echo "$*")" >> "$tsv"; return 0; }
[ -n "$tsv" ] && printf 'model\tlayer_mm\ttool\tmetric\tvalue\n' > "$tsv"

# ---------------------------------------------------------------- header
commit=$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)
dirty=$(git -C "$repo" status --porcelain --untracked-files=no 2>/dev/null | grep -q . && echo " (+ uncommitted changes)" || true)
echo "# maxslice vs peer slicers  $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "commit $commit$dirty; maxslice: $maxslice (--threads $threads)"
echo "machine: $(nproc) cores, $(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo), $(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo); $(. /etc/os-release; echo "$PRETTY_NAME")"
for p in "${peers[@]}"; do
    case $p in
        prusa) echo "peer PrusaSlicer $(dpkg-query -W -f '${Version}' prusa-slicer 2>/dev/null)" ;;
        cura) echo "peer CuraEngine $(dpkg-query -W -f '${Version}' cura-engine 2>/dev/null)  (CURA_DEFS=$CURA_DEFS)" ;;
        slic3r) echo "peer Slic3r $(dpkg-query -W -f '${Version}' slic3r 2>/dev/null)" ;;
    esac
done
echo "runs: median of $runs after 1 warm-up (warm page cache); load average at start: $(cut -d' ' -f1-3 /proc/loadavg); other work now: $(idle_sample 1) cores"
echo

# ---------------------------------------------------------------- the measurements
model_files=()
declare -A short              # file -> name shown in the tables
for name in "${model_names[@]}"; do
    f=$(model_path "$name"); model_files+=("$f")
    case $name in lattice) short[$f]=lattice_cone ;; *) short[$f]=$(basename "$f" .stl) ;; esac
done

for f in "${model_files[@]}"; do
    m=${short[$f]}
    echo "## $m  ($f, $(awk -v s="$(stat -c %s "$f")" 'BEGIN { printf "%.1f MB", s / 1e6 }'))"
    info_out=$("$maxslice" info "$f" 2>&1) || true
    head -n 14 <<< "$info_out" | sed "s/^/    /"

    # Plain read of the file, warm cache; then the same read with the file's pages dropped
    # first (dd iflag=nocache asks the kernel to drop them; on a VM the host may still cache
    # them): what a job's first read costs.
    cat "$f" > /dev/null
    read_s=$(time_reads "$f" warm)
    R["$m|read"]=$read_s
    emit_tsv "$m" - cat read_s "$read_s"
    echo "plain read (cat FILE > /dev/null, warm cache, median of $read_runs): $(num "$read_s" 4) s"
    cold_s=$(time_reads "$f" cold)
    R["$m|cold"]=$cold_s
    emit_tsv "$m" - cat cold_read_s "$cold_s"
    echo "cold read (the same after dd iflag=nocache dropped the file's pages, median of $read_runs): $(num "$cold_s" 4) s"
    echo

    for L in "${layers[@]}"; do
        k=$m.$L
        matched_profile "$L" > "$work/matched.toml"
        # --allow-overhangs: the peers print overhangs on air too (no supports); maxslice
        # would refuse a 3-axis program for a part that needs a multi-axis build.
        job=("$maxslice" slice "$f" --layer "$L" --profile "$work/matched.toml" -o "$work/out.ngc"
             --timings --threads "$threads" --allow-overhangs)
        measure "$k.maxslice" "${job[@]}"
        for s in "${ms_stages[@]}"; do R["$m|$L|ms_$s"]=$(ms_stage "$k.maxslice" "$s"); done
        R["$m|$L|ms_exit"]=$(exits "$k.maxslice")
        if [ "${R[$m|$L|ms_exit]}" != 0 ]; then
            # Refused (e.g. an open mesh, which the peers repair silently): time it again with
            # --repair (repairs are in its validate stage); if that fails too, the load and
            # validate stages come from `info`.
            R["$m|$L|ms_error"]=$(grep -m1 -h "error" "$work/$k.maxslice.err1" | sed "s/^maxslice: //" || true)
            measure "$k.msrepair" "${job[@]}" --repair
            if [ "$(exits "$k.msrepair")" = 0 ]; then
                R["$m|$L|ms_note"]="with --repair"
                for s in "${ms_stages[@]}"; do R["$m|$L|ms_$s"]=$(ms_stage "$k.msrepair" "$s"); done
            else
                R["$m|$L|ms_note"]="refused, load from info"
                measure "$k.msinfo" "$maxslice" info "$f" --timings --threads "$threads"
                for s in load validate; do R["$m|$L|ms_$s"]=$(ms_stage "$k.msinfo" "$s"); done
            fi
        fi
        # The same job without the verifier's replay (the peers do not check their programs):
        # the like-for-like figure beside the default job.
        nv_job=("${job[@]}" --no-verify)
        [ "${R[$m|$L|ms_note]:-}" = "with --repair" ] && nv_job+=(--repair)
        [ "${R[$m|$L|ms_note]:-}" != "refused, load from info" ] && measure "$k.msnover" "${nv_job[@]}"
        rm -f "$work/out.ngc"
        if [ "$whole" = 1 ]; then
            for p in "${peers[@]}"; do
                measure "$k.$p" "$peers_dir/slice_$p.sh" "$f" "$L" "$work/out.gcode"
                rm -f "$work/out.gcode"
            done
        fi
        if [[ " ${peers[*]} " == *" slic3r "* ]]; then
            measure "$k.slic3r-svg" env SVG_ONLY=1 "$peers_dir/slice_slic3r.sh" "$f" "$L" "$work/out.svg"
            rm -f "$work/out.svg"
        fi
        # PrusaSlicer's and CuraEngine's own stage times (stages.py runs both, $runs times).
        if [[ " ${peers[*]} " == *" prusa "* || " ${peers[*]} " == *" cura "* ]]; then
            wait_for_idle
            b0=$(busy_jiffies); t0=$EPOCHREALTIME
            "$gnu_time" -o "$work/time.out" -f '%U %S' \
                python3 "$peers_dir/stages.py" "$f" "$L" "$runs" > "$work/$k.stages" 2>/dev/null || true
            t1=$EPOCHREALTIME; b1=$(busy_jiffies)
            R["$m|$L|stages_foreign"]=$(awk -v t0="$t0" -v t1="$t1" -v b="$((b1 - b0))" -v hz="$hz" \
                'END { f = (b / hz - $1 - $2) / (t1 - t0); printf "%.2f", f < 0 ? 0 : f }' "$work/time.out")
            while IFS=$'\t' read -r _ _ peer load slice _; do
                [ "$peer" = peer ] && continue
                [ "$load" = failed ] && { R["$m|$L|${peer}_load"]=failed; continue; }
                R["$m|$L|${peer}_load"]=$load; R["$m|$L|${peer}_slice"]=$slice
            done < "$work/$k.stages"
        fi

        # ---- report for this model and layer
        echo "### $m, layer $L mm"
        echo
        echo "Whole job: mesh in, program out, matched settings (ratios against maxslice's own run; with --repair when it refused). maxslice replays every program it writes in its verifier; the --no-verify row is the same job without that check (the peers check nothing)"
        echo
        printf '| %-22s | %5s | %8s | %8s | %8s | %12s | %11s | %11s | %7s |\n' tool exit "wall s" "cpu s" \
            "peak MiB" "wall peer/ms" "cpu peer/ms" "MiB peer/ms" foreign
        printf '|%s|%s:|%s:|%s:|%s:|%s:|%s:|%s:|%s:|\n' ------------------------ ------ --------- --------- \
            --------- ------------- ------------ ------------ --------
        tools=(maxslice)
        [ "${R[$m|$L|ms_note]:-}" = "with --repair" ] && tools+=(msrepair)
        [ "${R[$m|$L|ms_note]:-}" != "refused, load from info" ] && tools+=(msnover)
        [ "$whole" = 1 ] && tools+=("${peers[@]}")
        [[ " ${peers[*]} " == *" slic3r "* ]] && tools+=(slic3r-svg)
        ms_key=maxslice; [ "${R[$m|$L|ms_note]:-}" = "with --repair" ] && ms_key=msrepair
        ms_wall=$(col "$k.$ms_key" 1); ms_cpu=$(cpu_med "$k.$ms_key"); ms_rss=$(rss_med "$k.$ms_key")
        R["$m|$L|ms_wall"]=$ms_wall
        for t in "${tools[@]}"; do
            wall=$(col "$k.$t" 1); cpu=$(cpu_med "$k.$t"); rss=$(rss_med "$k.$t")
            label=$t
            case $t in
                prusa) label="PrusaSlicer" ;; cura) label="CuraEngine" ;; slic3r) label="Slic3r" ;;
                slic3r-svg) label="Slic3r --export-svg" ;;
                msrepair) label="maxslice --repair" ;;
                msnover) label="maxslice --no-verify" ;;
            esac
            printf '| %-22s | %5s | %8s | %8s | %8s | %12s | %11s | %11s | %7s |\n' "$label" "$(exits "$k.$t")" \
                "$(num "$wall")" "$(num "$cpu" 2)" "$(num "$rss" 0)" "$(ratio "$wall" "$ms_wall")" \
                "$(ratio "$cpu" "$ms_cpu")" "$(ratio "$rss" "$ms_rss")" "$(max_foreign "$k.$t")"
            R["$m|$L|${t}_wall"]=$wall; R["$m|$L|${t}_cpu"]=$cpu; R["$m|$L|${t}_rss"]=$rss
            emit_tsv "$m" "$L" "$t" wall_s "$wall"; emit_tsv "$m" "$L" "$t" cpu_s "$cpu"
            emit_tsv "$m" "$L" "$t" peak_MiB "$rss"; emit_tsv "$m" "$L" "$t" exit "$(exits "$k.$t")"
        done
        [ -n "${R[$m|$L|ms_error]:-}" ] && echo "${R[$m|$L|ms_error]}"
        echo
        echo "Stages (s; median of $runs; peers' from their own logs, foreign load during them ${R[$m|$L|stages_foreign]:--} cores)"
        echo
        printf '| %-26s | %8s | %8s | %8s | %8s | %8s | %12s | %13s |\n' tool load validate slice \
            paths write "load peer/ms" "slice peer/ms"
        printf '|%s|%s:|%s:|%s:|%s:|%s:|%s:|%s:|\n' ---------------------------- --------- --------- \
            --------- --------- --------- -------------- ---------------
        printf '| %-26s | %8s | %8s | %8s | %8s | %8s | %12s | %13s |\n' \
            "maxslice${R[$m|$L|ms_note]:+ (${R[$m|$L|ms_note]})}" "$(num "${R[$m|$L|ms_load]}")" \
            "$(num "${R[$m|$L|ms_validate]}")" "$(num "${R[$m|$L|ms_slice]}")" \
            "$(num "${R[$m|$L|ms_paths]:-}")" "$(num "${R[$m|$L|ms_write]:-}")" 1.00 1.00
        for p in prusa cura; do
            [[ " ${peers[*]} " == *" $p "* ]] || continue
            label=PrusaSlicer; [ $p = cura ] && label=CuraEngine
            printf '| %-26s | %8s | %8s | %8s | %8s | %8s | %12s | %13s |\n' "$label" \
                "$(num "${R[$m|$L|${p}_load]:-}")" - "$(num "${R[$m|$L|${p}_slice]:-}")" - - \
                "$(ratio "${R[$m|$L|${p}_load]:-}" "${R[$m|$L|ms_load]}")" \
                "$(ratio "${R[$m|$L|${p}_slice]:-}" "${R[$m|$L|ms_slice]}")"
            emit_tsv "$m" "$L" "$p" stage_load_s "${R[$m|$L|${p}_load]:-}"
            emit_tsv "$m" "$L" "$p" stage_slice_s "${R[$m|$L|${p}_slice]:-}"
        done
        if [[ " ${peers[*]} " == *" slic3r "* ]]; then
            ms_ls=$(awk -v a="${R[$m|$L|ms_load]}" -v b="${R[$m|$L|ms_slice]}" 'BEGIN { print a + b }')
            printf '| %-26s | %8s | %8s | %8s | %8s | %8s | %12s | %13s |\n' "Slic3r (svg, whole)" - - \
                "$(num "${R[$m|$L|slic3r-svg_wall]}")" - - - "$(ratio "${R[$m|$L|slic3r-svg_wall]}" "$ms_ls")"
            echo "(Slic3r: whole --export-svg process, incl. start-up and load; its ratio is against maxslice load + slice)"
        fi
        for s in "${ms_stages[@]}"; do emit_tsv "$m" "$L" maxslice "stage_${s}_s" "${R[$m|$L|ms_$s]:-}"; done
        echo
    done
done

# ---------------------------------------------------------------- targets
verdict() {                 # verdict RATIO OP LIMIT
    awk -v v="$1" -v op="$2" -v l="$3" 'BEGIN {
        if (v == "-") { print "n/a"; exit }
        ok = (op == ">=") ? v + 0 >= l : (op == ">") ? v + 0 > l : v + 0 <= l
        print ok ? "holds" : "FAILS" }'
}
echo "## Targets"
echo
echo "(a) maxslice load (read + weld) at least 3x faster than CuraEngine's load stage"
echo "(b) maxslice slice stage faster than CuraEngine's slice stage"
echo "(c) maxslice slice stage within 2x of the plain read time of the file (cat, warm cache)"
echo
printf '| %-26s | %5s | %8s | %9s | %11s | %-6s | %8s | %10s | %12s | %-6s | %8s | %10s | %-6s |\n' \
    model layer "ms load" "cura load" "cura/ms" "(a)" "ms slice" "cura slice" "cura/ms" "(b)" "read" "ms slice/read" "(c)"
printf '|%s|%s:|%s:|%s:|%s:|%s|%s:|%s:|%s:|%s|%s:|%s:|%s|\n' ---------------------------- ------ --------- ---------- \
    ------------ -------- --------- ----------- ------------- -------- --------- ----------- --------
for f in "${model_files[@]}"; do
    m=${short[$f]}
    for L in "${layers[@]}"; do
        ml=${R[$m|$L|ms_load]}; ms=${R[$m|$L|ms_slice]}
        cl=${R[$m|$L|cura_load]:-}; cs=${R[$m|$L|cura_slice]:-}
        rd=${R[$m|read]}
        ra=$(ratio "$cl" "$ml"); rb=$(ratio "$cs" "$ms"); rc=$(ratio "$ms" "$rd")
        label=$m; [ "${R[$m|$L|ms_note]:-}" = "with --repair" ] && label="$m (--repair)"
        printf '| %-26s | %5s | %8s | %9s | %11s | %-6s | %8s | %10s | %12s | %-6s | %8s | %10s | %-6s |\n' \
            "$label" "$L" "$(num "$ml")" "$(num "$cl")" "$ra" "$(verdict "$ra" ">=" 3)" "$(num "$ms")" \
            "$(num "$cs")" "$rb" "$(verdict "$rb" ">" 1)" "$(num "$rd" 4)" "$rc" "$(verdict "$rc" "<=" 2)"
        emit_tsv "$m" "$L" target a_ratio "$ra"; emit_tsv "$m" "$L" target b_ratio "$rb"
        emit_tsv "$m" "$L" target c_ratio "$rc"
    done
done
echo
echo "(a) holds when cura/ms >= 3; (b) when cura/ms > 1; (c) when maxslice slice / plain read <= 2."
echo
echo "For reference, not the target's measure: the slice stage against a cold read of the file"
echo "(its pages dropped first), what the first job on a newly written file pays to read it."
echo
printf '| %-26s | %5s | %8s | %9s | %14s |\n' model layer "ms slice" "cold read" "slice/cold"
printf '|%s|%s:|%s:|%s:|%s:|\n' ---------------------------- ------ --------- ---------- ----------------
for f in "${model_files[@]}"; do
    m=${short[$f]}
    for L in "${layers[@]}"; do
        ms=${R[$m|$L|ms_slice]}; cr=${R[$m|cold]}
        printf '| %-26s | %5s | %8s | %9s | %14s |\n' "$m" "$L" "$(num "$ms")" "$(num "$cr" 4)" \
            "$(ratio "$ms" "$cr")"
    done
done
echo
if [ "$whole" = 1 ] && [ ${#peers[@]} -gt 0 ]; then
    # The largest model: the most triangles (file size for STL).
    largest=; largest_size=0
    for f in "${model_files[@]}"; do
        sz=$(stat -c %s "$f"); [ "$sz" -gt "$largest_size" ] && { largest_size=$sz; largest=${short[$f]}; }
    done
    echo "(d) maxslice whole job (mesh in, program out) faster than every peer's whole job"
    echo "(e) on the largest model ($largest): maxslice whole job at least 3x faster than the fastest peer"
    echo
    printf '| %-26s | %5s | %8s | %-22s | %9s | %10s | %-6s | %-6s |\n' model layer "ms wall" \
        "fastest peer" "its wall" "peer/ms" "(d)" "(e)"
    printf '|%s|%s:|%s:|%s|%s:|%s:|%s|%s|\n' ---------------------------- ------ --------- \
        ------------------------ ----------- ------------ -------- --------
    for f in "${model_files[@]}"; do
        m=${short[$f]}
        for L in "${layers[@]}"; do
            mw=${R[$m|$L|ms_wall]:-nan}; best=; bw=
            for p in "${peers[@]}"; do
                [ "$(exits "$m.$L.$p")" = 0 ] || continue     # a peer that failed does not count
                w=${R[$m|$L|${p}_wall]:-nan}
                if [ -z "$bw" ] || awk -v a="$w" -v b="$bw" 'BEGIN { exit !(a < b) }'; then bw=$w; best=$p; fi
            done
            rr=$(ratio "$bw" "$mw")
            ve=-; [ "$m" = "$largest" ] && ve=$(verdict "$rr" ">=" 3)
            [ "${R[$m|$L|ms_exit]:-}" != 0 ] && [ "${R[$m|$L|ms_note]:-}" != "with --repair" ] && rr=-
            label=$m; [ "${R[$m|$L|ms_note]:-}" = "with --repair" ] && label="$m (--repair)"
            case $best in prusa) best=PrusaSlicer ;; cura) best=CuraEngine ;; slic3r) best=Slic3r ;; esac
            printf '| %-26s | %5s | %8s | %-22s | %9s | %10s | %-6s | %-6s |\n' "$label" "$L" "$(num "$mw")" \
                "${best:--}" "$(num "$bw")" "$rr" "$(verdict "$rr" ">" 1)" "$ve"
            emit_tsv "$m" "$L" target d_ratio "$rr"
        done
    done
    echo
    echo "(d) holds when the fastest peer's wall / maxslice's wall > 1 (then every peer is slower); (e) when >= 3."
fi
for f in "${model_files[@]}"; do
    m=${short[$f]}
    for L in "${layers[@]}"; do
        [ -n "${R[$m|$L|ms_error]:-}" ] &&
            echo "$m $L mm: maxslice without --repair refused to slice (exit ${R[$m|$L|ms_exit]}; stages above: ${R[$m|$L|ms_note]}): ${R[$m|$L|ms_error]}"
    done
done
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg); largest foreign load in any timed run is in the 'foreign' columns (cores)."
