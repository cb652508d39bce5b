#!/usr/bin/env bash
# Runs the libFuzzer harnesses of a build for a fixed time each, on copies of the corpus in
# fuzz/corpus (the repository is never written), and prints each harness's figures.
#   fuzz/run.sh [-b BUILD_DIR] [-t SECONDS] [-j JOBS] [-o OUT_DIR] [-T TIMEOUT] [HARNESS...]
# Defaults: build/asan, 60 s, 2 at a time, a fresh temporary folder, every harness, 30 s
# for one input (raise -T on a loaded machine, where a niced run can be starved that long).
# Fails (exit 1) when a harness crashes, hangs past -timeout, runs out of memory, leaks or
# breaks an invariant; the input is then OUT_DIR/<harness>/crash-* (or timeout-*, oom-*,
# leak-*), and the log OUT_DIR/<harness>/log. Replay one with: BUILD_DIR/fuzz/<harness> FILE
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build/asan"
seconds=60
jobs=2
out=""
timeout=30
while getopts "b:t:j:o:T:" opt; do
  case "$opt" in
    b) build="$(cd "$OPTARG" && pwd)" ;;
    t) seconds="$OPTARG" ;;
    j) jobs="$OPTARG" ;;
    o) out="$OPTARG" ;;
    T) timeout="$OPTARG" ;;
    *) exit 2 ;;
  esac
done
shift $((OPTIND - 1))
harnesses=("$@")
if ((${#harnesses[@]} == 0)); then
  for d in "$root"/fuzz/corpus/*/; do harnesses+=("$(basename "$d")"); done
fi
# Leaks inside the libraries behind the readers are suppressed in the harnesses
# (fuzz_read.hpp); do not list the suppressions after every leak check.
export LSAN_OPTIONS="${LSAN_OPTIONS:-print_suppressions=0}"
# clang-16's runtime does not find Debian's llvm-symbolizer by itself: name it, so that the
# reports show functions and lines.
if [ -z "${ASAN_SYMBOLIZER_PATH:-}" ]; then
  for s in llvm-symbolizer-16 llvm-symbolizer; do
    if command -v "$s" >/dev/null; then
      ASAN_SYMBOLIZER_PATH="$(command -v "$s")"
      export ASAN_SYMBOLIZER_PATH
      break
    fi
  done
fi
[ -n "$out" ] || out="$(mktemp -d "${TMPDIR:-/tmp}/maxslice-fuzz.XXXXXX")"
mkdir -p "$out"

run_one() {
  local h="$1" dir="$out/$1"
  mkdir -p "$dir/corpus"
  cp -r "$root/fuzz/corpus/$h/." "$dir/corpus/"
  # -timeout: one input may take 30 s (the STEP reader's child has a 10 s limit);
  # -rss_limit_mb: 2 GB (a reader must refuse, not allocate, a file's absurd counts).
  # fuzz_3mf: libzip leaks on every 3MF read (suppressed), which would make libFuzzer run a
  # full leak check after every input and halve the rate; leaks are left to the tests there.
  local extra=()
  [ "$h" != fuzz_3mf ] || extra=(-detect_leaks=0)
  "$build/fuzz/$h" -max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2048 \
    "${extra[@]}" -print_final_stats=1 -artifact_prefix="$dir/" "$dir/corpus" >"$dir/log" 2>&1
}

pids=()
names=()
for h in "${harnesses[@]}"; do
  [ -x "$build/fuzz/$h" ] || { echo "fuzz: $build/fuzz/$h is not built" >&2; exit 2; }
  while (($(jobs -rp | wc -l) >= jobs)); do sleep 1; done
  run_one "$h" &
  pids+=($!)
  names+=("$h")
done

failed=0
printf '%-14s %10s %8s %7s %7s %6s  %s\n' harness executions exec/s cov ft corpus result
for i in "${!pids[@]}"; do
  h="${names[$i]}"
  status=0
  wait "${pids[$i]}" || status=$?
  log="$out/$h/log"
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)"
  last="$(grep -E '^#[0-9]+.*cov: ' "$log" | tail -1 || true)"
  cov="$(sed -n 's/.*cov: \([0-9]*\).*/\1/p' <<<"$last")"
  ft="$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")"
  corp="$(sed -n 's/.*corp: \([0-9]*\)\/.*/\1/p' <<<"$last")"
  result="ok"
  if ((status != 0)); then
    failed=1
    result="FAILED (exit $status): $(ls "$out/$h" | grep -E '^(crash|timeout|oom|leak)-' | head -1)"
  fi
  printf '%-14s %10s %8s %7s %7s %6s  %s\n' "$h" "${execs:-?}" "${rate:-?}" "${cov:-?}" \
    "${ft:-?}" "${corp:-?}" "$result"
done
if ((failed)); then
  echo "fuzz: a harness failed; logs and inputs in $out" >&2
  exit 1
fi
echo "fuzz: logs in $out"
