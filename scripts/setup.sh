#!/usr/bin/env bash
# Installs the Debian packages this project needs; does nothing when all are installed.
# Used by the README's two commands and by .ci/run. Debian 12 (bookworm), as root or with sudo.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config make
  libeigen3-dev libopencv-dev libpng-dev libhdf5-dev libboost-graph-dev nlohmann-json3-dev libssl-dev
  libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-h5py python3-numpy python3-matplotlib
)
# Optional: Debian's colmap (COLMAP 3.8, CPU SIFT) for tests/e2e/test_colmap.py and the
# photos-to-model route of docs/colmap.md; Debian's chromium for the report's browser check
# (tests/e2e/test_report.py). Tried once, never fatal (the tests skip what needs them).
OPTIONAL=(colmap chromium)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
optional=()
for p in "${OPTIONAL[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || optional+=("$p")
done
if [ ${#missing[@]} -eq 0 ] && [ ${#optional[@]} -eq 0 ]; then
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
if [ ${#optional[@]} -gt 0 ]; then
  # never fatal: a machine without network (or without the package) skips what needs it
  echo "setup: trying the optional ${optional[*]}" >&2
  { [ ${#missing[@]} -gt 0 ] || timeout 300 $SUDO apt-get update -q; } >/dev/null 2>&1 || true
  if timeout 900 $SUDO apt-get install -y -q --no-install-recommends "${optional[@]}" >/dev/null 2>&1; then
    echo "setup: installed ${optional[*]}" >&2
  else
    echo "setup: optional ${optional[*]} not installed (the tests that need it are skipped)" >&2
  fi
fi
