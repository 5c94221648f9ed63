#!/usr/bin/env bash
# Fuzzes every reader with libFuzzer (clang) under AddressSanitizer (with leak
# detection) and UndefinedBehaviorSanitizer (any report stops the run), SECONDS
# each (default 60), one target at a time in one process (no -jobs), starting
# from the seed corpus fuzz/corpus/<target>/. What libFuzzer finds is kept in
# build-fuzz/findings/<target>/ (crash-*, leak-*, timeout-*, oom-* files); a
# finding, once fixed, belongs in fuzz/corpus/<target>/, which the tests replay
# (ctest -R fuzz_replay). Prints one line per target: seconds, executions,
# corpus size, findings; the same lines go to build-fuzz/summary.txt.
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]
# FUZZ_BUILD_JOBS sets the build's parallelism (default: every core).
# FUZZ_RUNS=N makes each run deterministic: at most N inputs with libFuzzer's
# seed 1 (SECONDS still caps it). CI runs `FUZZ_RUNS=20000 scripts/fuzz.sh 30`
# after the tests (.ci/run).
# See docs/fuzzing.md.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}; shift || true
all=(log_native log_carmen log_ev3 log_auto world_aria robot_json png plan_json cdr store)
targets=("$@")
if ((${#targets[@]} == 0)); then targets=("${all[@]}"); fi
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "fuzz.sh: unknown target $t (${all[*]})" >&2; exit 2; }
done

bash scripts/install-deps.sh --fuzz
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCOGMAP_FUZZ=ON \
  -DCOGMAP_BUILD_TESTS=OFF -DCOGMAP_BUILD_BENCH=OFF -DCOGMAP_BUILD_PYTHON=OFF -DCOGMAP_BUILD_ROS=OFF >/dev/null
cmake --build build-fuzz -j"${FUZZ_BUILD_JOBS:-$(nproc)}" --target "${targets[@]/#/cogmap_fuzz_}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
status=0
: >build-fuzz/summary.txt
for t in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$t findings=build-fuzz/findings/$t log=build-fuzz/$t.log
  mkdir -p "$corpus" "$findings"
  cp -n fuzz/corpus/"$t"/* "$corpus"/ 2>/dev/null || true
  before_list=$(mktemp)
  find "$findings" -type f -printf '%f\n' | sort >"$before_list"
  echo "== $t ($seconds s)"
  rc=0
  limits=(-max_total_time="$seconds")
  if [[ -n "${FUZZ_RUNS:-}" ]]; then limits+=(-runs="$FUZZ_RUNS" -seed=1); fi
  build-fuzz/fuzz/cogmap_fuzz_"$t" "$corpus" "${limits[@]}" \
    -rss_limit_mb=2048 -timeout=10 -artifact_prefix="$findings/" -print_final_stats=1 >"$log" 2>&1 || rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -1)
  new_files=$(find "$findings" -type f -printf '%f\n' | sort | comm -13 "$before_list" -)
  rm -f "$before_list"
  found=$(printf '%s' "$new_files" | grep -c . || true)
  # A damaged bag or rawlog is read first in a forked child with bounded
  # memory (cogmap/io/child_check.h); the child inherits libFuzzer's malloc
  # limit and, hitting it, leaves an oom-* artifact for the input before it
  # dies, while the parent refuses the input and goes on (libFuzzer exits 0).
  # Such artifacts are the bound working, not findings; a real out-of-memory
  # ends libFuzzer itself with a non-zero exit.
  child_oom=0
  if ((rc == 0 && found > 0)); then
    child_oom=$(printf '%s' "$new_files" | grep -c '^oom-' || true)
    found=$((found - child_oom))
  fi
  note=""
  if ((child_oom > 0)); then note=", $child_oom bounded child(ren) out of memory (refused)"; fi
  line="$t: ${seconds} s${FUZZ_RUNS:+ or $FUZZ_RUNS runs}, ${execs:-?} executions, corpus $(find "$corpus" -type f | wc -l) files, peak RSS ${rss:-?} MB, ${found} new finding(s)${note}, exit $rc"
  echo "$line" | tee -a build-fuzz/summary.txt
  if ((rc != 0 || found > 0)); then
    echo "$t: see $findings and $log"; status=1
  fi
done
exit $status
