#!/usr/bin/env bash
# Set up (packages, build) and run the whole test suite with ctest: unit tests,
# multi-process scenarios, the fault-injection suite (docs/reliability.md),
# the PIC18 build run in gpsim, and a bounded
# libFuzzer run of the protocol decoder.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
JOBS="${JOBS:-2}"
# the PIC18 cross-build: SDCC's pic16 port from Debian's source package, cached
# outside the repository after the first build (a few minutes), then every
# firmware program to a .hex; the gpsim tests in ctest run these
tools/pic-build.sh
ctest --test-dir build --output-on-failure -j "$JOBS" --timeout 600

# the fuzzer needs clang: its own small build of only the fuzz target
if [ ! -f build-fuzz/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCHAINSIM_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
cmake --build build-fuzz -j "$JOBS" --target protocol_fuzz
ctest --test-dir build-fuzz --output-on-failure -R fuzz
