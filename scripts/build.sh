#!/usr/bin/env bash
# Configures and builds the project into build/ (Release, Ninja). Extra args go to cmake.
# A fresh build directory is configured as a unity build (CMakeLists.txt, TETMVS_UNITY:
# a clean build in 55 % of the time); TETMVS_UNITY=OFF bash scripts/build.sh configures
# a per-file build instead, quicker to rebuild after editing one file. An existing build
# directory keeps its configuration.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTETMVS_UNITY="${TETMVS_UNITY:-ON}" "$@" >/dev/null
fi
ninja -C "$BUILD_DIR" ${NINJA_FLAGS:-}
