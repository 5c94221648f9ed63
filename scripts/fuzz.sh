#!/usr/bin/env bash
# Fuzzes every reader with libFuzzer (clang) under AddressSanitizer and
# UndefinedBehaviorSanitizer, SECONDS each (default 60), starting from the seed
# corpus (fuzz/corpus/<target>/); what libFuzzer finds is kept in
# build-fuzz/findings/<target>/ (crash-*, timeout-*, oom-* files). A finding,
# once fixed, belongs in fuzz/corpus/<target>/, which the tests replay.
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}; shift || true
bash scripts/install-deps.sh
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev >/dev/null
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCOGMAP_FUZZ=ON \
  -DCOGMAP_BUILD_TESTS=OFF -DCOGMAP_BUILD_BENCH=OFF -DCOGMAP_BUILD_PYTHON=OFF -DCOGMAP_BUILD_ROS=OFF >/dev/null
targets=("$@")
if ((${#targets[@]} == 0)); then
  targets=(log_native log_carmen log_ev3 log_auto world_aria robot_json png plan_json cdr)
fi
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]/#/cogmap_fuzz_}"
status=0
for t in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$t findings=build-fuzz/findings/$t
  mkdir -p "$corpus" "$findings"
  cp -n fuzz/corpus/"$t"/* "$corpus"/ 2>/dev/null || true
  echo "== $t ($seconds s)"
  if ! build-fuzz/fuzz/cogmap_fuzz_"$t" "$corpus" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
       -artifact_prefix="$findings/" -print_final_stats=1 2>"build-fuzz/$t.log"; then
    echo "$t: finding(s) in $findings (log: build-fuzz/$t.log)"; status=1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "build-fuzz/$t.log" || true
done
exit $status
