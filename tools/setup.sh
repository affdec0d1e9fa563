#!/usr/bin/env bash
# Set-up for a fresh Debian 12 machine: installs the Debian packages chainsim
# needs when any is missing, configures and builds (incrementally) in build/.
# Used by tools/run-default.sh and tools/test-all.sh; safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

# What building chainsim, its evaluator and the programs needs (the CMake
# target chainsim-tools, tools/run-default.sh)
RUN_PACKAGES=(
  build-essential cmake pkg-config
  libode-dev libyaml-cpp-dev libcli11-dev libboost-dev libeigen3-dev libassimp-dev
  nlohmann-json3-dev libssl-dev libgtest-dev
  libnlopt-cxx-dev                # chainsim calibrate: the optimiser (NLopt BOBYQA)
  libpagmo-dev                    # chainsim optimize: the genetic algorithm (pagmo sga)
  libre2-dev                      # chainsim test: log patterns matched by RE2, in linear time
  libopenmpi-dev                  # chainsim optimize under mpirun (MPI ranks)
)
# and what the rest of the build and the tests need
TEST_PACKAGES=(
  git python3
  libxml2-utils                   # xmllint: the tests validate the JUnit report against the CI schemas
  doxygen                         # the HAL reference (build/docs/hal-reference), built with the project
  openmpi-bin                     # mpirun
  slurm-wlm munge                 # tools/slurm's job script, tested under a one-node Slurm the test starts itself
  clang libclang-rt-14-dev        # libFuzzer target of the protocol decoder
  chromium                        # chainsim view --png and the viewer tests (headless)
  gpsim gpsim-dev libglib2.0-dev  # chainsim-pic: the board's .hex in gpsim (target: pic)
)
# SETUP_PACKAGES=run: only RUN_PACKAGES (tools/run-default.sh; tools/test-all.sh
# installs the rest later)
PACKAGES=("${RUN_PACKAGES[@]}")
if [ "${SETUP_PACKAGES:-all}" != run ]; then
  PACKAGES+=("${TEST_PACKAGES[@]}")
  # node and npm bundle the viewer (tools/viewer); a node >= 18 already installed will do
  command -v node >/dev/null && command -v npm >/dev/null || PACKAGES+=(nodejs npm)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
installed=0
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  t0=$SECONDS
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
  echo "setup: ${#missing[@]} packages installed in $((SECONDS - t0)) s"
  installed=1
fi

JOBS="${JOBS:-2}"
# a build/ whose configure never finished (a CMakeCache.txt and no build
# files: cmake was run before the packages were there) is configured again
if [ -f build/CMakeCache.txt ] && [ ! -f build/Makefile ] && [ ! -f build/build.ninja ]; then
  echo "setup: build/ was left half-configured (no Makefile): configuring it again"
  rm -f build/CMakeCache.txt
fi
t0=$SECONDS
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
elif [ "$installed" = 1 ] || { [ "${SETUP_PACKAGES:-all}" != run ] &&
                               grep -qE '^(CHAINSIM_NODE|GPSIM_LIBRARY|DOXYGEN_EXECUTABLE):[A-Z]+=.*-NOTFOUND$' build/CMakeCache.txt; }; then
  # packages came in since build/ was configured (gpsim, doxygen, node: parts
  # built only when found): configure again so that they are found
  echo "setup: configuring build/ again for the packages installed since"
  cmake -S . -B build >/dev/null
fi
# SETUP_TARGET: only that target (tools/run-default.sh: what a run needs)
if [ -n "${SETUP_TARGET:-}" ]; then
  cmake --build build -j "$JOBS" --target "$SETUP_TARGET"
else
  cmake --build build -j "$JOBS"
fi
echo "setup: build/ up to date in $((SECONDS - t0)) s"
