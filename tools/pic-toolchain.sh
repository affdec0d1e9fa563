#!/usr/bin/env bash
# Build the PIC18 toolchain for hal-pic (docs: hal-pic/README.md, "Toolchain and build"):
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
# re-runs when the generator or the toolchain script's code changes. The source
# (src/, 175 MB) is only used to build; it may be deleted afterwards.
# Idempotent; takes about 2 minutes on 2 cores the first time, <1 s cached.
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
trap 'rc=$?; [ $rc -eq 0 ] || printf "[pic-toolchain] FAILED (exit %s); logs: %s/logs\n" "$rc" "$CACHE" >&2' EXIT

mkdir -p "$CACHE/logs" || die "cannot create the cache directory $CACHE (set CHAINSIM_PIC_CACHE)"

# one writer at a time: checkouts on the same machine share the cache, and
# pic-build.sh holds the lock shared while it links against the runtime
exec 9>"$CACHE/lock"
if ! flock -n 9; then
  say "waiting for another user of $CACHE"
  flock 9
fi

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

# what is missing: the source (175 MB unpacked and built) is only needed to
# build the compiler or the runtime, so a cache without it is still complete
mkdir -p "$CACHE/stamps"
SRC_STAMP="$CACHE/stamps/source"
SDCC_PREFIX="$CACHE/sdcc"
SDCC_BIN="$SDCC_PREFIX/bin/sdcc"
COMP_STAMP="$CACHE/stamps/compiler"
RT="$CACHE/rt"
RT_STAMP="$CACHE/stamps/runtime"
# the runtime is rebuilt when this script or the header generator changes;
# not for an edit of the script's comment lines (the cache is shared by every
# checkout on the machine, and each would rebuild it for the other)
RT_KEY=$({ grep -vE '^[[:space:]]*#( |$)' "${BASH_SOURCE[0]}"; cat "$HERE/pic-devhdr.py" "$INC_FILE"; } |
  sha256sum | cut -c1-16)
need_compiler=0
need_runtime=0
if [ ! -f "$COMP_STAMP" ] || [ ! -x "$SDCC_BIN" ] || [ ! -x "$SDCC_PREFIX/bin/sdcpp" ]; then
  need_compiler=1
  need_runtime=1
fi
for f in crt0i.o stack.o "pic$DEVICE.o" libsdcc.lib; do
  [ -f "$RT/$f" ] || need_runtime=1
done
if [ ! -f "$RT_STAMP" ] || [ "$(cat "$RT_STAMP")" != "$RT_KEY" ]; then
  need_runtime=1
fi

# ---- 2. SDCC source ------------------------------------------------------------
if [ $need_compiler -eq 0 ] && [ $need_runtime -eq 0 ]; then
  say "SDCC source not needed (compiler and runtime cached)"
elif [ ! -f "$SRC_STAMP" ] || [ ! -d "$(cat "$SRC_STAMP" 2>/dev/null)" ]; then
  if [ "$(id -u)" -ne 0 ] && [ -z "$SUDO" ]; then
    die "need root (or sudo) to add a deb-src entry to apt"
  fi
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
  # the source index may be there already (deb-src entry added and updated before)
  if ! apt-cache showsrc sdcc 2>/dev/null | grep -q '^Package: sdcc'; then
    apt_update
  fi
  say "apt-get source sdcc (into $CACHE/src)"
  rm -rf "$CACHE/src"
  mkdir -p "$CACHE/src"
  # as root, apt downloads as the unprivileged _apt user: let it write there
  if [ "$(id -u)" -eq 0 ]; then chmod 0777 "$CACHE/src"; fi
  (cd "$CACHE/src" && run_logged apt-source.log apt-get source sdcc) ||
    die "apt-get source sdcc failed"
  srcdir=$(find "$CACHE/src" -mindepth 1 -maxdepth 1 -type d -name 'sdcc-*' | head -n 1)
  [ -n "$srcdir" ] && [ -f "$srcdir/configure" ] || die "no SDCC source tree under $CACHE/src"
  echo "$srcdir" >"$SRC_STAMP"
  # another SDCC version than the compiler was built from: build it again
  if [ -f "$COMP_STAMP" ] && [ "$(cat "$COMP_STAMP")" != "$srcdir" ]; then
    need_compiler=1
    need_runtime=1
  fi
else
  say "SDCC source cached"
fi
SDCC_SRC="$(cat "$SRC_STAMP" 2>/dev/null || true)"

# ---- 3. the compiler (pic16 port only) ----------------------------------------
if [ $need_compiler -eq 1 ]; then
  t0=$(date +%s)
  # every port but pic16, as configure lists them
  disable_ports=()
  for p in $(cd "$SDCC_SRC" && ./configure --help | grep -oE -- '--(disable|enable)-[a-z0-9_]+-port' |
             sed -E 's/^--(disable|enable)-//; s/-port$//' | sort -u); do
    case "$p" in
      pic16) ;;
      *) disable_ports+=("--disable-$p-port") ;;
    esac
  done
  say "configuring SDCC (pic16 only; ${#disable_ports[@]} other ports disabled)"
  (cd "$SDCC_SRC" && run_logged sdcc-configure.log ./configure --prefix="$SDCC_PREFIX" \
      --enable-pic16-port --disable-pic14-port --disable-ucsim --disable-sdcdb --disable-non-free \
      --disable-device-lib --disable-packihx --disable-sdbinutils "${disable_ports[@]}")
  # the top-level make would also want sdbinutils and the device libraries
  # (which need the non-free device files): build only the preprocessor and
  # the compiler
  say "building sdcpp and sdcc with $JOBS jobs (about 2 minutes)"
  run_logged sdcc-make-cpp.log make -C "$SDCC_SRC/support/cpp" -j "$JOBS"
  run_logged sdcc-make-src.log make -C "$SDCC_SRC/src" -j "$JOBS"
  [ -x "$SDCC_SRC/bin/sdcc" ] && [ -x "$SDCC_SRC/bin/sdcpp" ] || die "the SDCC build made no bin/sdcc or bin/sdcpp"
  # install by hand: binaries + the free headers (include, include/pic16, asm)
  rm -rf "$SDCC_PREFIX"
  mkdir -p "$SDCC_PREFIX/bin" "$SDCC_PREFIX/share/sdcc/include"
  cp "$SDCC_SRC/bin/sdcc" "$SDCC_SRC/bin/sdcpp" "$SDCC_PREFIX/bin/"
  strip "$SDCC_PREFIX/bin/sdcc" "$SDCC_PREFIX/bin/sdcpp" 2>/dev/null || true
  cp "$SDCC_SRC"/device/include/*.h "$SDCC_PREFIX/share/sdcc/include/"
  cp -r "$SDCC_SRC/device/include/pic16" "$SDCC_SRC/device/include/asm" "$SDCC_PREFIX/share/sdcc/include/"
  "$SDCC_BIN" -v >/dev/null 2>&1 || die "the installed $SDCC_BIN does not run"
  "$SDCC_BIN" -v 2>/dev/null | grep -q pic16 || die "$SDCC_BIN has no pic16 port"
  echo "$SDCC_SRC" >"$COMP_STAMP" # the source it was built from
  say "compiler built in $(( $(date +%s) - t0 )) s: $("$SDCC_BIN" -v | head -n 1)"
else
  say "compiler cached: $("$SDCC_BIN" -v | head -n 1)"
fi

# ---- 4 + 5. device header and runtime (a few seconds) ---------------------------
if [ $need_runtime -eq 1 ]; then
  t0=$(date +%s)
  say "generating the p$DEVICE device header from $INC_FILE"
  rm -rf "$CACHE/gen" "$RT"
  mkdir -p "$CACHE/gen" "$RT/obj"
  run_logged devhdr.log python3 "$HERE/pic-devhdr.py" "$INC_FILE" "$CACHE/gen"
  cp "$CACHE/gen/pic$DEVICE.h" "$SDCC_PREFIX/share/sdcc/include/pic16/"

  say "building the runtime (crt0i, SFR definitions, libsdcc helpers, string functions)"
  LIB="$SDCC_SRC/device/lib/pic16"
  # the flags SDCC's own pic16 library build uses
  RT_CFLAGS=(-mpic16 "-p$DEVICE" --std-c11 --no-warn-non-free --fomit-frame-pointer
             --obanksel=9 --denable-peeps --optimize-cmp --optimize-df -Wa,-q)
  rt_cc() { # source object
    run_logged "rt-$(basename "$2" .o).log" "$SDCC_BIN" "${RT_CFLAGS[@]}" -I"$LIB/libsdcc" -c "$1" -o "$2"
  }
  (
    cd "$RT/obj"
    rt_cc "$LIB/startup/crt0i.c" "$RT/crt0i.o"
    rt_cc "$CACHE/gen/pic$DEVICE.c" "$RT/pic$DEVICE.o"
    run_logged rt-stack.log gpasm "-p$DEVICE" -q -c "$LIB/libsdcc/stack/stack.S" -o "$RT/stack.o"
    n=0
    for src in "$LIB"/libsdcc/{char,int,long,gptr,lregs,float}/*.c "$LIB"/libc/string/*.c; do
      rt_cc "$src" "$RT/obj/$(basename "$src" .c).o"
      n=$((n + 1))
    done
    # libsdcc's generic-pointer helpers reach EEPROM through ___eeprom_gptr*,
    # which SDCC's non-free device library provides: the 18F2550 has 256 bytes
    # of EEPROM, so they are the 8-bit-address versions
    for k in get1 get2 get3 get4 put1 put2 put3 put4; do
      cat >"eeglue_gptr$k.S" <<ASM
; generated by tools/pic-toolchain.sh: ___eeprom_gptr$k -> ___eeprom8_gptr$k
        radix dec
        global ___eeprom_gptr$k
        extern ___eeprom8_gptr$k
eeglue_$k code
___eeprom_gptr$k:
        goto ___eeprom8_gptr$k
        end
ASM
      run_logged "rt-eeglue-$k.log" gpasm "-p$DEVICE" -q -c "eeglue_gptr$k.S" -o "eeglue_gptr$k.o"
    done
    rm -f "$RT/libsdcc.lib"
    run_logged rt-gplib.log gplib -c "$RT/libsdcc.lib" ./*.o
    say "runtime: crt0i.o, stack.o, pic$DEVICE.o, libsdcc.lib ($n C sources + 8 EEPROM glue stubs)"
  ) || die "building the runtime failed"
  echo "$RT_KEY" >"$RT_STAMP"
  say "runtime built in $(( $(date +%s) - t0 )) s"
else
  say "device header and runtime cached"
fi

# what tools/pic-build.sh needs
cat >"$CACHE/toolchain.env" <<ENV
# generated by tools/pic-toolchain.sh
PIC_CACHE=$CACHE
PIC_DEVICE=$DEVICE
PIC_SDCC=$SDCC_BIN
PIC_RUNTIME=$RT
PIC_LKR=$LKR_FILE
ENV
say "ready in $(( $(date +%s) - T_START )) s: $CACHE"
