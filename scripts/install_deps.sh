#!/usr/bin/env bash
# Installs every build and run dependency of the project from Debian 12 packages.
# Nothing is downloaded at build time and nothing is vendored: this is the only place
# where the project's dependencies are listed.
set -euo pipefail

packages=(
  build-essential cmake git
  libeigen3-dev            # Eigen 3.4
  libopencv-dev libopencv-contrib-dev   # OpenCV 4.6 with contrib (line detection, LK)
  libceres-dev             # Ceres 2.1 (Taylor & Kriegman baseline)
  libgtest-dev libgmock-dev
  libbenchmark-dev         # Google Benchmark (Table 1)
  nlohmann-json3-dev       # JSON configs and the stereo-lines/1 format
  libcli11-dev             # command-line parsing
  python3-matplotlib python3-numpy      # plots, for /usr/bin/python3
  clang libclang-rt-14-dev # libFuzzer, ASan + UBSan (scripts/sanitizer_tests.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
