#!/bin/bash
# Runs libFuzzer targets for a bounded time each and prints executions and coverage per target
# (docs/fuzzing.md):
#   tools/fuzz-run.sh BUILD_DIR SECONDS [TARGET...]     (default: every target)
# Each target grows its corpus in BUILD_DIR/fuzz-corpus/<target> from BUILD_DIR/fuzz-seeds/<target>
# (tools/fuzz-seeds.sh), tests/fuzz/seeds/<target> and tests/fuzz/regressions/<target>; a crash
# leaves its input in BUILD_DIR/fuzz-artifacts/ and fails the run. JOBS targets run at once
# (default 2); FUZZ_ARGS adds libFuzzer flags (e.g. "-fork=4 -ignore_crashes=1" for long runs).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: tools/fuzz-run.sh BUILD_DIR SECONDS [TARGET...]}
seconds=${2:?usage: tools/fuzz-run.sh BUILD_DIR SECONDS [TARGET...]}
shift 2
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(camera cryptomatte exr profile scene texture)
jobs=${JOBS:-2}
# Fake stacks for use-after-return halve the executions per second; the test suite keeps them.
export ASAN_EXTRA_OPTIONS="detect_stack_use_after_return=0${ASAN_EXTRA_OPTIONS:+:$ASAN_EXTRA_OPTIONS}"
# shellcheck source=tools/sanitizers/env.sh
. tools/sanitizers/env.sh
mkdir -p "$build/fuzz-artifacts" "$build/fuzz-logs"

run_one() {
  local t=$1 corpus="$build/fuzz-corpus/$1"
  mkdir -p "$corpus"
  local dirs=("$corpus")
  for d in "$build/fuzz-seeds/$t" "tests/fuzz/seeds/$t" "tests/fuzz/regressions/$t"; do
    [ -d "$d" ] && dirs+=("$d")
  done
  # -timeout: an input that takes 20 s is a finding too (a hostile file must fail fast).
  local rc=0
  # shellcheck disable=SC2086
  "$build/tests/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2560 -print_final_stats=1 \
    -artifact_prefix="$build/fuzz-artifacts/$t-" ${FUZZ_ARGS:-} "${dirs[@]}" >"$build/fuzz-logs/$t.log" 2>&1 || rc=$?
  echo "$rc" >"$build/fuzz-logs/$t.rc"
}

summary() {
  local t=$1 log="$build/fuzz-logs/$1.log" rc=$2
  local execs rate cov ft
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  printf '%-12s %12s %10s %8s %8s  %s\n' "$t" "${execs:--}" "${rate:--}" "${cov:--}" "${ft:--}" \
    "$([ "$rc" -eq 0 ] && echo ok || echo "FAILED (rc $rc, $log)")"
}

for t in "${targets[@]}"; do
  [ -x "$build/tests/fuzz/fuzz_$t" ] || { echo "no fuzz target $build/tests/fuzz/fuzz_$t (build with DECALCOMP_FUZZ=ON)" >&2; exit 2; }
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 1; done
  run_one "$t" &
done
wait
failed=0
declare -A codes
for t in "${targets[@]}"; do
  codes[$t]=$(cat "$build/fuzz-logs/$t.rc")
  [ "${codes[$t]}" -eq 0 ] || failed=1
done
printf '%-12s %12s %10s %8s %8s  %s\n' target executions exec/s cov ft result
for t in "${targets[@]}"; do summary "$t" "${codes[$t]}"; done
if [ "$failed" -ne 0 ]; then
  for t in "${targets[@]}"; do
    [ "${codes[$t]}" -eq 0 ] && continue
    echo "---- $t: tail of $build/fuzz-logs/$t.log"
    tail -n 60 "$build/fuzz-logs/$t.log"
  done
  echo "Crash inputs are in $build/fuzz-artifacts/; each becomes a regression test (docs/fuzzing.md)." >&2
  exit 1
fi
