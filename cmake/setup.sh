#!/usr/bin/env bash
# One-stop set-up on Debian 12: installs the packages Parallax needs (when missing), configures,
# builds, and then runs the demo or the test suite.
#
#   bash cmake/setup.sh demo    # install what `parallax` needs, build only it, score the Census
#                               # design on the shipped KITTI crops (README: about 5 min fresh)
#   bash cmake/setup.sh test    # install the rest (test, lint and browser tools), build
#                               # everything, run the whole test suite (ctest)
#   bash cmake/setup.sh build   # install everything and build every target
#
# Environment: PARALLAX_PRESET (release | ci | debug; default release), PARALLAX_JOBS.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# What the `parallax` executable needs to build and run (the demo installs only these).
RUN_PACKAGES=(build-essential cmake ninja-build pkg-config
              libopencv-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
              libceres-dev libeigen3-dev libsqlite3-dev libpugixml-dev libmuparser-dev)
# What the tests, the lint and the tools add: GoogleTest, Chromium (the HTML report tests),
# clang-format/-tidy and ctags (lint), yosys and python3 (the operator table of the resource
# model, models/resources/tools), git.
TEST_PACKAGES=(git libgtest-dev libgmock-dev chromium clang-format clang-tidy universal-ctags
               yosys python3)
# Optional: the MPI mode of `parallax sweep` is built when OpenMPI is present; node and npm
# fetch the independent MAVLink decoder the tests cross-check with.
OPTIONAL_PACKAGES=(libopenmpi-dev openmpi-bin)
PRESET="${PARALLAX_PRESET:-release}"
JOBS="${PARALLAX_JOBS:-$(nproc)}"

# deps PACKAGE...: installs those of the packages that are missing.
deps() {
  local missing=()
  for p in "$@"; do
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
  deps "${RUN_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
  optional_deps
  npm_deps
  cmake --preset "$PRESET" -DPARALLAX_BUILD_TESTS=ON >/dev/null
  cmake --build --preset "$PRESET" -j "$JOBS"
}

# Only the executable: no test packages, no test targets (a later `test` turns them on in the
# same build directory and reuses what is built).
build_parallax() {
  deps "${RUN_PACKAGES[@]}"
  if [ -f "build/$PRESET/CMakeCache.txt" ]; then
    cmake --preset "$PRESET" >/dev/null  # keep the test targets of an earlier full build
  else
    cmake --preset "$PRESET" -DPARALLAX_BUILD_TESTS=OFF -DPARALLAX_UNITY=ON >/dev/null
  fi
  cmake --build --preset "$PRESET" -j "$JOBS" --target parallax
}

bin() { echo "build/$PRESET/explore/parallax"; }

case "${1:-}" in
  build)
    build
    ;;
  demo)
    build_parallax
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
