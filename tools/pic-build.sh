#!/usr/bin/env bash
# Build every firmware program for the PIC18F2550 board with hal-pic:
# the toolchain first (tools/pic-toolchain.sh: cached after the first run),
# then the standalone CMake project hal-pic/ into OUTDIR (default build-pic).
# Prints each program's flash/RAM use; fails when one is over the part's
# limits. Results: OUTDIR/<program>.hex (+ .cod for gpsim, .map, .size).
#
# Usage: tools/pic-build.sh [outdir]
# Environment: CHAINSIM_PIC_CACHE (toolchain cache), JOBS
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-$ROOT/build-pic}"
JOBS="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
export CHAINSIM_PIC_CACHE="${CHAINSIM_PIC_CACHE:-$HOME/.cache/chainsim-pic}"

"$ROOT/tools/pic-toolchain.sh"
# keep the runtime from being rebuilt under us (pic-toolchain.sh takes the
# lock exclusively)
exec 9>"$CHAINSIM_PIC_CACHE/lock"
flock -s 9

echo "[pic-build] building the firmware into $OUT"
cmake -S "$ROOT/hal-pic" -B "$OUT" -DCHAINSIM_PIC_CACHE="$CHAINSIM_PIC_CACHE" >/dev/null
cmake --build "$OUT" -j "$JOBS"

echo "[pic-build] PIC18F2550 programs:"
shopt -s nullglob
sizes=("$OUT"/*.size)
[ ${#sizes[@]} -gt 0 ] || { echo "[pic-build] ERROR: no program was built" >&2; exit 1; }
for s in "${sizes[@]}"; do
  echo "  $(cat "$s")"
done
