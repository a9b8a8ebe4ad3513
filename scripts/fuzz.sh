#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/*.cpp) with clang, ASan and UBSan, and runs each for
# a bounded time (FUZZ_SECONDS, default 60). Inputs that crash are copied into
# tests/fuzz_corpus/<target>/, which the unit tests replay (FuzzRegression.*).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${FUZZ_SECONDS:-60}
if ! command -v clang++ >/dev/null; then
  echo "fuzz: needs clang (apt-get install clang libclang-rt-14-dev)" >&2; exit 1
fi
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTETMVS_FUZZ=ON -DTETMVS_TESTS=OFF -DTETMVS_BENCH=OFF >/dev/null
fi
ninja -C build-fuzz fuzz_par fuzz_params fuzz_h5
for t in par params h5; do
  corpus=tests/fuzz_corpus/$t
  work=$(mktemp -d)
  cp -r "$corpus"/. "$work"/ 2>/dev/null || true
  echo "== fuzz_$t for ${SECONDS_EACH}s"
  if ! build-fuzz/bin/fuzz_$t "$work" -max_total_time="$SECONDS_EACH" -artifact_prefix="$corpus/crash-" \
       -print_final_stats=1 2>&1 | tail -5; then
    echo "fuzz_$t found a crash: see $corpus/crash-*" >&2
  fi
  rm -rf "$work"
done
