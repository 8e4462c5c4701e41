#!/usr/bin/env bash
# Installs the Debian 12 packages dba needs to build, test and run (as root).
# Idempotent: does nothing when everything is already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build
  libeigen3-dev libbz2-dev bzip2 nlohmann-json3-dev
  libgtest-dev googletest libbenchmark-dev
  openmpi-bin libopenmpi-dev
  libsuitesparse-dev libopenblas0-pthread
  libproj-dev libxxhash-dev
  time
  colmap
  python3-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: need root to install packages (run as root or with sudo)" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
