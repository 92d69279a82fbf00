#!/usr/bin/env bash
# Sets up (packages, data, the Release build whose CLI writes seed files), builds the libFuzzer
# targets (CMakePresets.json's `fuzz`: clang, ASan and UBSan, in build-fuzz/), makes their seed
# corpus once (fuzz/make_corpus.sh), and runs each fuzzer (or the one named: `body_obj` or
# `body_obj_fuzzer`) for SECONDS (default 30), niced. Each fuzzer's corpus grows in
# build-fuzz/corpus/<fuzzer>/ from run to run; a crash, leak, timeout or out-of-memory input is
# kept in build-fuzz/crashes/<fuzzer>/ (reproduce: build-fuzz/fuzz/<fuzzer>_fuzzer FILE). Ends
# with a table per fuzzer (executions, coverage, crashes) and exits non-zero if any fuzzer
# failed. Usage: scripts/fuzz.sh [TARGET] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
only=${1:-}
seconds=${2:-30}
if [[ ! "$only" =~ ^[a-z_]*$ || ! "$seconds" =~ ^[0-9]+$ ]]; then
  echo "usage: scripts/fuzz.sh [TARGET] [SECONDS]" >&2
  exit 2
fi
build="$root/build-fuzz"

scripts/setup.sh
mkdir -p "$build"
cmake --preset fuzz > "$build/configure.log" 2>&1 || { cat "$build/configure.log"; exit 1; }
nice -n 10 cmake --build --preset fuzz

# Inputs stay near the size of the real files they come from; larger ones only slow the run.
max_len() {
  case "$1" in
    avatar_basis_fuzzer|garment_fuzzer|drape_task_spec_fuzzer) echo 1500000 ;;
    avatar_fuzzer|clothing_basis_fuzzer|drape_result_fuzzer|http_body_fuzzer) echo 400000 ;;
    draco_positions_fuzzer|body_obj_fuzzer|garment_obj_fuzzer|mhclo_fuzzer) echo 65536 ;;
    *) echo 16384 ;;
  esac
}

mapfile -t fuzzers < "$build/fuzz/fuzzers.txt"
# The seeds are made once, and again when a fuzzer has none yet (one added since).
for fuzzer in "${fuzzers[@]}"; do
  if [ ! -d "$build/seeds/${fuzzer%_fuzzer}" ]; then
    nice -n 10 fuzz/make_corpus.sh "$build"
    break
  fi
done
if [ -n "$only" ]; then
  name=${only%_fuzzer}_fuzzer
  printf '%s\n' "${fuzzers[@]}" | grep -qx "$name" || {
    echo "fuzz: no fuzzer $only; there are: ${fuzzers[*]%_fuzzer}" >&2
    exit 2
  }
  fuzzers=("$name")
fi

export FITBASE_FUZZ_CATALOGUE="$build/seeds/catalogue"
# Stack traces name functions and lines when LLVM's symbolizer is installed (package llvm-16).
[ -x /usr/lib/llvm-16/bin/llvm-symbolizer ] &&
  export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-16/bin/llvm-symbolizer
# Leaks count as failures; UBSan stops at the first error like ASan.
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
terminal=false
[ -t 2 ] && terminal=true
total=${#fuzzers[@]}
start=$(date +%s)
failed=0
rows=()
for k in "${!fuzzers[@]}"; do
  fuzzer=${fuzzers[$k]}
  target=${fuzzer%_fuzzer}
  corpus="$build/corpus/$target"
  crashes="$build/crashes/$target"
  log="$build/logs/$target.log"
  mkdir -p "$corpus" "$crashes" "$build/logs"
  before=$(find "$crashes" -type f | wc -l)
  nice -n 10 "$build/fuzz/$fuzzer" -max_total_time="$seconds" -max_len="$(max_len "$fuzzer")" \
    -timeout=30 -rss_limit_mb=2560 -print_final_stats=1 -artifact_prefix="$crashes/" \
    "$corpus" "$build/seeds/$target" > "$log" 2>&1 &
  pid=$!
  t0=$(date +%s)
  while kill -0 "$pid" 2>/dev/null; do
    if $terminal; then
      now=$(date +%s)
      remaining=$(( (total - k) * seconds - (now - t0) ))
      printf '\rfuzz %d/%d %-22s elapsed %4ds  ETA %4ds ' "$((k + 1))" "$total" "$target" \
        "$((now - start))" "$(( remaining > 0 ? remaining : 0 ))" >&2
    fi
    sleep 1
  done
  status=0
  wait "$pid" || status=$?
  $terminal && printf '\r\033[K' >&2
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -n 1 | cut -d' ' -f2)
  ft=$(grep -oE 'ft: [0-9]+' "$log" | tail -n 1 | cut -d' ' -f2)
  found=$(( $(find "$crashes" -type f | wc -l) - before ))
  verdict=ok
  if [ "$status" -ne 0 ]; then
    verdict="FAILED (exit $status, $log)"
    failed=$((failed + 1))
  fi
  echo "fuzz $((k + 1))/$total $target: ${execs:-?} executions, cov ${cov:-?}, ft ${ft:-?}," \
    "$found new crash files: $verdict"
  rows+=("$(printf '%-20s %12s %7s %7s %8s  %s' "$target" "${execs:-?}" "${cov:-?}" "${ft:-?}" \
    "$found" "$verdict")")
done

echo
printf '%-20s %12s %7s %7s %8s  %s\n' fuzzer executions cov ft crashes result
printf '%s\n' "${rows[@]}"
echo "fuzz: ${seconds} s per fuzzer, $(( $(date +%s) - start )) s in all;" \
  "crash inputs in $build/crashes/"
[ "$failed" -eq 0 ]
