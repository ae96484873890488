#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, and only those that are missing.
# Idempotent: a second run installs nothing and prints nothing but its summary line.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libceres-dev libeigen3-dev libsuitesparse-dev
  libgdal-dev libproj-dev libhdf5-dev libssl-dev
  libyaml-cpp-dev libcli11-dev libgtest-dev
  coinor-libipopt-dev
  python3-h5py python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
