#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs every test, then
# rebuilds with AddressSanitizer + UndefinedBehaviorSanitizer and runs the unit tests and
# the small end-to-end run under them.
#   SANITIZE=0 bash scripts/test.sh   skips the sanitizer pass
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
start=$(date +%s)
echo "== build (Release)"
bash scripts/build.sh
echo "== tests (Release)"
(cd build && ctest --output-on-failure -j2 --timeout 900)
echo "== release pass took $(( $(date +%s) - start )) s"
if [ "${SANITIZE:-1}" != "0" ]; then
  echo "== build (ASan + UBSan)"
  if [ ! -f build-asan/build.ninja ]; then
    cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTETMVS_SANITIZE=ON \
      -DTETMVS_BENCH=OFF >/dev/null
  fi
  ninja -C build-asan
  echo "== tests (ASan + UBSan)"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  (cd build-asan && ctest --output-on-failure -j2 --timeout 1200 -R "^(e2e_test_pipeline|[A-Z])" -E "Slow")
fi
echo "== all tests took $(( $(date +%s) - start )) s"
