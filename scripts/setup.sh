#!/usr/bin/env bash
# Installs the Debian packages this project needs; does nothing when all are installed.
# Used by the README's two commands and by .ci/run. Debian 12 (bookworm), as root or with sudo.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config make
  libeigen3-dev libopencv-dev libhdf5-dev libboost-graph-dev nlohmann-json3-dev
  libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-h5py python3-numpy python3-matplotlib
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
