#!/usr/bin/env bash
# One-stop set-up on Debian 12: installs the packages Parallax needs (when missing), configures,
# builds, and then runs the demo or the test suite.
#
#   bash cmake/setup.sh demo    # build, then score the Census design on the shipped KITTI crops
#   bash cmake/setup.sh test    # build, then run the whole test suite (ctest)
#   bash cmake/setup.sh build   # install and build only
#
# Environment: PARALLAX_PRESET (release | ci | debug; default release), PARALLAX_JOBS.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

PACKAGES=(build-essential cmake ninja-build pkg-config git
          libopencv-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev
          libceres-dev libeigen3-dev libsqlite3-dev libpugixml-dev chromium libmuparser-dev
          clang-format clang-tidy universal-ctags
          yosys python3)  # yosys: the operator table of the resource model (models/resources/tools)
# Optional: the MPI mode of `parallax sweep` is built when OpenMPI is present; node and npm
# fetch the independent MAVLink decoder the tests cross-check with.
OPTIONAL_PACKAGES=(libopenmpi-dev openmpi-bin)
PRESET="${PARALLAX_PRESET:-release}"
JOBS="${PARALLAX_JOBS:-$(nproc)}"

deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "setup: installing ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

optional_deps() {
  local missing=()
  for p in "${OPTIONAL_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "setup: installing optional ${missing[*]}" >&2
  $sudo apt-get update -qq >/dev/null 2>&1 || true
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null 2>&1 ||
    echo "setup: optional ${missing[*]} not installed; what needs them is left out" >&2
}

# The independent MAVLink decoder of the tests (node-mavlink from the npm registry); the test is
# skipped when it cannot be installed.
npm_deps() {
  local dir=tests/explore/uav/mavlink_node
  [ -d "$dir/node_modules/node-mavlink" ] && return 0
  if ! command -v npm >/dev/null 2>&1; then  # Debian's packages, when no node is installed at all
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null 2>&1 || return 0
  fi
  (cd "$dir" && npm install --no-audit --no-fund --loglevel=error >/dev/null 2>&1) ||
    echo "setup: npm install in $dir failed; the node-mavlink cross-check is skipped" >&2
}

build() {
  deps
  optional_deps
  npm_deps
  cmake --preset "$PRESET" >/dev/null
  cmake --build --preset "$PRESET" -j "$JOBS"
}

bin() { echo "build/$PRESET/explore/parallax"; }

case "${1:-}" in
  build)
    build
    ;;
  demo)
    build
    mkdir -p out
    "$(bin)" eval --config configs/ruf2018-census.yaml --dataset data/kitti2015-640x360 --save out/census
    "$(bin)" run --config configs/ruf2018-census.yaml \
      --left data/kitti2015-640x360/training/image_2/000001_10.png \
      --right data/kitti2015-640x360/training/image_3/000001_10.png \
      --gt data/kitti2015-640x360/training/disp_noc_0/000001_10.png --out out/000001_disparity.png
    ;;
  test)
    build
    ctest --test-dir "build/$PRESET" --output-on-failure -j "$JOBS"
    ;;
  *)
    echo "usage: bash cmake/setup.sh demo|test|build" >&2
    exit 2
    ;;
esac
