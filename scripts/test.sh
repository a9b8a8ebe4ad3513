#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs every test, then
# rebuilds with AddressSanitizer + UndefinedBehaviorSanitizer and runs the unit tests and a
# mini end-to-end pipeline under them, and the hostile-input tests (tests/e2e/test_hostile.py --quick).
#   SANITIZE=0 bash scripts/test.sh       skips the sanitizer pass
#   SANITIZE_E2E=1 bash scripts/test.sh   also runs the small pipeline under the sanitizers
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
    cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_FLAGS_SANITIZE="-O1" \
      -DTETMVS_SANITIZE=ON -DTETMVS_BENCH=OFF -DTETMVS_UNITY="${TETMVS_UNITY:-ON}" >/dev/null
  fi
  ninja -C build-asan  # the unit tests and the programs in one call: the cores stay busy
  echo "== ASan build took $(( $(date +%s) - start )) s since the start"
  echo "== tests (ASan + UBSan)"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # the unit tests (one process: the sanitizers' start-up cost once). Skipped here: the
  # PhotoconsistScene tests (rendered scenes, whole level passes: minutes under the
  # sanitizers, and .ci/run measured 19m57s with them) and the DeformScene tests that deform
  # whole rendered scenes (77 s under the sanitizers; .ci/run measured 19m04s with them), and
  # the five label tests that label whole synthetic scenes (42 s of the 125 s the unit tests
  # take under the sanitizers), and the three slowest scene tests of label, silhouette-fix and
  # evaluate (29 s of 150; .ci/run measured 19m04s with them). The Release pass runs them, and
  # the mini pipeline below runs photoconsist's passes, label, silhouette-fix, deform and
  # evaluate under the sanitizers.
  build-asan/bin/unit_tests --gtest_brief=1 \
    --gtest_filter='-PhotoconsistScene.*:DeformScene.Textured*:DeformScene.Textureless*:DeformScene.WithoutSilhouettes*:DeformScene.HalfSteps*:Label.ConflictingLabelsFromQAreLeftFree:Label.VotedOutCellsLieDeepInsideTheHull:Label.CupLabelsAreNeverWrong:Label.SeenFreeSpaceLeavesTheHullCoreAndTheVotesAlone:Label.FewViewsSeeingThroughDoNotOutweighManyHidingViews:Label.PointsInFreeSpaceAreDropped:SilFix.HornConstraintsAreCorrectAndRecutRecoversTheProtrusion:Evaluate.ConvexLidOfTheCupMissesTheCavity'
  # every stage end to end on a mini scene (16 views of 160 x 120, 2 levels: under a minute; the
  # programs were built above); a sanitizer report aborts its stage, so make fails. SANITIZE_E2E=1 runs the
  # larger e2e pipeline test under the sanitizers instead (about 10 more minutes).
  echo "== ASan unit tests done $(( $(date +%s) - start )) s since the start"
  echo "== mini pipeline (ASan + UBSan)"
  mini=build-asan/e2e-mini
  rm -rf "$mini"
  make -s -f pipeline.mk BUILD_DIR="$PWD/build-asan" DATA=synth-sphere SYNTH_DIR="$PWD/$mini/data" \
    RUN_DIR="$PWD/$mini/run" SYNTH_CAMERAS=ring "SYNTH_FLAGS=--views 16 --size 160x120" LEVELS=2 \
    MESH_CELLS=8 QUIET=1 final evaluate
  /usr/bin/python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['completeness']['value']; \
print('mini pipeline under sanitizers: final completeness', c); sys.exit(0 if c > 0.9 else 1)" "$mini/run/eval_final.json"
  # hostile files, a full disk, nonsense scenes on a 6-view scene of 64 x 48 (the failure
  # paths: a sanitizer report is one more line and fails the test)
  echo "== hostile inputs (ASan + UBSan)"
  /usr/bin/python3 tests/e2e/test_hostile.py build-asan/bin . --quick
  if [ "${SANITIZE_E2E:-0}" = "1" ]; then
    /usr/bin/python3 tests/e2e/test_pipeline.py build-asan/bin .
  fi
fi
echo "== all tests took $(( $(date +%s) - start )) s"
