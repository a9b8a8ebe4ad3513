#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/*.cpp) with clang, ASan and UBSan, and runs each for a
# bounded time, one after the other on one core:
#   FUZZ_SECONDS=300 bash scripts/fuzz.sh            # all targets (default 60 s each)
#   FUZZ_SECONDS=60 bash scripts/fuzz.sh par h5      # some of them (par, params, h5)
# fuzz/<target>.dict, when present, is passed as the libFuzzer dictionary.
# Every input that crashes, leaks, times out or trips UBSan is written to
# tests/fuzz_corpus/<target>/crash-* (or leak-*, timeout-*, oom-*); the unit tests replay
# that folder (FuzzRegression.*), so keep the file once the bug is fixed.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${FUZZ_SECONDS:-60}
BUILD=${FUZZ_BUILD_DIR:-build-fuzz}
TARGETS=${*:-par params h5}
if ! command -v clang++ >/dev/null; then
  echo "fuzz: needs clang (apt-get install clang libclang-rt-14-dev)" >&2; exit 1
fi
if [ ! -f "$BUILD/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTETMVS_FUZZ=ON -DTETMVS_TESTS=OFF -DTETMVS_BENCH=OFF >/dev/null
fi
ninja -C "$BUILD" -j"${FUZZ_JOBS:-2}" $(for t in $TARGETS; do echo "fuzz_$t"; done)
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export ASAN_OPTIONS=detect_leaks=1
status=0
for t in $TARGETS; do
  corpus=tests/fuzz_corpus/$t
  work=$(mktemp -d)
  cp -r "$corpus"/. "$work"/ 2>/dev/null || true
  echo "== fuzz_$t for ${SECONDS_EACH}s"
  log=$(mktemp)
  dict=(); [ -f "fuzz/$t.dict" ] && dict=(-dict="fuzz/$t.dict")
  if "$BUILD/bin/fuzz_$t" "$work" -max_total_time="$SECONDS_EACH" -timeout=20 -rss_limit_mb=2048 \
       -artifact_prefix="$corpus/" -print_final_stats=1 "${dict[@]}" >"$log" 2>&1; then
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb|cov:" "$log" | tail -3
  else
    status=1
    grep -E "ERROR|runtime error|SUMMARY|Test unit written|stat::number_of_executed_units" "$log" | head -8
    echo "fuzz_$t found a problem: see $corpus/ (log $log)" >&2
  fi
  rm -rf "$work"
done
exit $status
