#!/usr/bin/env bash
# Build firmware for the PIC18F2550 board with hal-pic: the toolchain first
# (tools/pic-toolchain.sh: cached after the first run), then
#
#   tools/pic-build.sh [outdir]
#       every firmware/*/main.c of this tree: the standalone CMake project
#       hal-pic/ into OUTDIR (default build/pic, where chainsim looks for
#       the .hex of a module whose target is pic): OUTDIR/fw-<program>.hex
#       (+ .cod for gpsim, .map, .size, .pic.json)
#   tools/pic-build.sh --project DIR [outdir]
#       a program of your own (a CMake project using find_package(chainsim)
#       and chainsim_add_firmware, docs/firmware.md): configured with
#       -DCHAINSIM_PIC=ON into OUTDIR (default DIR/build-pic), against this
#       tree's build/ unless chainsim_DIR is set: OUTDIR/<program>.hex
#   --strict (before the rest): SDCC's warnings that mean the board computes
#       something else than a PC (integer overflow, a shift wider than int)
#       fail the build (tools/pic-cc.py; CHAINSIM_PIC_STRICT)
#
# Prints each program's flash/RAM use; fails when one is over the part's
# limits.
# Environment: CHAINSIM_PIC_CACHE (toolchain cache), JOBS, chainsim_DIR
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PROJECT=""
STRICT=OFF
if [ "${1:-}" = "--strict" ]; then
  STRICT=ON
  shift
fi
if [ "${1:-}" = "--project" ]; then
  [ -n "${2:-}" ] && [ -f "$2/CMakeLists.txt" ] || { echo "[pic-build] --project needs a folder with a CMakeLists.txt" >&2; exit 2; }
  PROJECT="$(cd "$2" && pwd)"
  shift 2
fi
OUT="${1:-${PROJECT:+$PROJECT/build-pic}}"
OUT="${OUT:-$ROOT/build/pic}"
JOBS="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
export CHAINSIM_PIC_CACHE="${CHAINSIM_PIC_CACHE:-$HOME/.cache/chainsim-pic}"

"$ROOT/tools/pic-toolchain.sh"
# keep the runtime from being rebuilt under us (pic-toolchain.sh takes the
# lock exclusively)
exec 9>"$CHAINSIM_PIC_CACHE/lock"
flock -s 9

if [ -n "$PROJECT" ]; then
  pkg="${chainsim_DIR:-$ROOT/build}"
  [ -f "$pkg/chainsimConfig.cmake" ] || { echo "[pic-build] no chainsimConfig.cmake in $pkg: build chainsim first, or set chainsim_DIR" >&2; exit 2; }
  echo "[pic-build] building $PROJECT into $OUT (chainsim package: $pkg)"
  cmake -S "$PROJECT" -B "$OUT" -Dchainsim_DIR="$pkg" -DCHAINSIM_PIC=ON -DCHAINSIM_PIC_CACHE="$CHAINSIM_PIC_CACHE" \
    -DCHAINSIM_PIC_STRICT=$STRICT >/dev/null
else
  echo "[pic-build] building the firmware into $OUT"
  cmake -S "$ROOT/hal-pic" -B "$OUT" -DCHAINSIM_PIC_CACHE="$CHAINSIM_PIC_CACHE" -DCHAINSIM_PIC_STRICT=$STRICT >/dev/null
fi
cmake --build "$OUT" -j "$JOBS"

echo "[pic-build] PIC18F2550 programs:"
shopt -s nullglob
sizes=("$OUT"/*.size)
[ ${#sizes[@]} -gt 0 ] || { echo "[pic-build] ERROR: no program was built" >&2; exit 1; }
for s in "${sizes[@]}"; do
  echo "  $(cat "$s")"
done
