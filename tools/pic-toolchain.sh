#!/usr/bin/env bash
# Build the PIC18 toolchain for hal-pic (docs: hal-pic/README.md, DESIGN.md 7):
#
#   1. Debian packages: gputils (gpasm/gplink/gplib, .inc and .lkr files),
#      gpsim, and the build dependencies of SDCC
#   2. a deb822 deb-src entry (only if apt has none), `apt-get source sdcc`
#   3. SDCC with only the pic16 port (bin/sdcc, bin/sdcpp)
#   4. the PIC18F2550 device header + SFR definitions, generated from gputils'
#      p18f2550.inc by tools/pic-devhdr.py
#   5. the runtime: crt0i (startup) and libsdcc helpers (integer multiply /
#      divide / modulo / shifts, generic pointers, ...) as gputils libraries
#
# Everything goes to a cache outside the repo:
#   ${CHAINSIM_PIC_CACHE:-$HOME/.cache/chainsim-pic}
# Each step has a stamp file and is skipped when done; the runtime step also
# re-runs when the generator or the toolchain script changes. Idempotent.
#
# Usage: tools/pic-toolchain.sh [--print-cache]
#   --print-cache   only print the cache directory
# Environment: CHAINSIM_PIC_CACHE, JOBS (default: nproc)
set -euo pipefail

CACHE="${CHAINSIM_PIC_CACHE:-$HOME/.cache/chainsim-pic}"
if [ "${1:-}" = "--print-cache" ]; then
  echo "$CACHE"
  exit 0
fi

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
JOBS="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
DEVICE=18f2550
T_START=$(date +%s)

say() { printf '[pic-toolchain] %s\n' "$*"; }
die() {
  printf '[pic-toolchain] ERROR: %s\n' "$*" >&2
  exit 1
}
trap 'rc=$?; [ $rc -eq 0 ] || printf "[pic-toolchain] FAILED (exit %s) at line %s; see the logs under %s/logs\n" "$rc" "$LINENO" "$CACHE" >&2' EXIT

mkdir -p "$CACHE/logs" || die "cannot create the cache directory $CACHE (set CHAINSIM_PIC_CACHE)"

# run a command with its output in a log file; show the log's tail on failure
run_logged() {
  local log="$CACHE/logs/$1"
  shift
  if ! "$@" >"$log" 2>&1; then
    tail -n 40 "$log" >&2
    die "'$*' failed (full log: $log)"
  fi
}

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; fi
fi

APT_UPDATED=0
apt_update() {
  if [ "$APT_UPDATED" -eq 0 ]; then
    say "apt-get update"
    run_logged apt-update.log $SUDO apt-get -o DPkg::Lock::Timeout=600 update
    APT_UPDATED=1
  fi
}

# ---- 1. packages -------------------------------------------------------------
PKGS=(gputils gpsim bison flex texinfo zlib1g-dev libboost-graph-dev autoconf automake
      dpkg-dev make gcc g++ python3)
missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -ne 0 ]; then
  if [ "$(id -u)" -ne 0 ] && [ -z "$SUDO" ]; then
    die "missing packages (${missing[*]}) and not root without sudo: install them first"
  fi
  apt_update
  say "installing ${missing[*]}"
  run_logged apt-install.log $SUDO env DEBIAN_FRONTEND=noninteractive \
    apt-get -o DPkg::Lock::Timeout=600 install -y --no-install-recommends "${missing[@]}"
else
  say "packages present"
fi

GPUTILS_SHARE=/usr/share/gputils
INC_FILE="$GPUTILS_SHARE/header/p$DEVICE.inc"
LKR_FILE="$GPUTILS_SHARE/lkr/${DEVICE}_g.lkr"
[ -f "$INC_FILE" ] || die "gputils has no $INC_FILE"
[ -f "$LKR_FILE" ] || die "gputils has no $LKR_FILE"
for t in gpasm gplink gplib gpsim; do
  command -v "$t" >/dev/null 2>&1 || die "$t not found after installing gputils/gpsim"
done

# ---- 2. SDCC source ------------------------------------------------------------
SRC_STAMP="$CACHE/stamps/source"
mkdir -p "$CACHE/stamps"
if [ ! -f "$SRC_STAMP" ] || [ ! -d "$(cat "$SRC_STAMP" 2>/dev/null)" ]; then
  # a deb-src entry, unless apt already has one (deb822 .sources or a one-line list)
  if ! grep -rqsE '^[[:space:]]*(Types:.*deb-src|deb-src[[:space:]])' \
      /etc/apt/sources.list /etc/apt/sources.list.d/ 2>/dev/null; then
    base=/etc/apt/sources.list.d/debian.sources
    [ -f "$base" ] || die "no $base to derive a deb-src entry from; add a deb-src entry for Debian main yourself"
    say "adding deb-src entry /etc/apt/sources.list.d/debian-src.sources (from $base)"
    # same stanzas (URIs, Suites, Components, Signed-By), Types: deb-src
    sed -E 's/^Types:.*/Types: deb-src/' "$base" | $SUDO tee /etc/apt/sources.list.d/debian-src.sources >/dev/null
    APT_UPDATED=0
  fi
  apt_update
  say "apt-get source sdcc (into $CACHE/src)"
  rm -rf "$CACHE/src"
  mkdir -p "$CACHE/src"
  # as root apt downloads as the _apt user: let it write there
  chmod 0777 "$CACHE/src"
  (cd "$CACHE/src" && run_logged apt-source.log apt-get source sdcc) ||
    die "apt-get source sdcc failed"
  srcdir=$(find "$CACHE/src" -mindepth 1 -maxdepth 1 -type d -name 'sdcc-*' | head -n 1)
  [ -n "$srcdir" ] && [ -f "$srcdir/configure" ] || die "no SDCC source tree under $CACHE/src"
  echo "$srcdir" >"$SRC_STAMP"
  rm -f "$CACHE/stamps/compiler" "$CACHE/stamps/runtime"
else
  say "SDCC source cached"
fi
SDCC_SRC="$(cat "$SRC_STAMP")"
