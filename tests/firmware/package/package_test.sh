#!/usr/bin/env bash
# The chainsim CMake package used as a firmware developer would, by ctest
# (tests/firmware/package/CMakeLists.txt):
#
#   install BUILD PREFIX          cmake --install BUILD --prefix PREFIX (fresh)
#   installed-run PREFIX WORK     the installed chainsim, run from WORK (outside
#                                 both trees): a scene of PREFIX/share/chainsim,
#                                 the built-in scene, a replay page
#   example MODE PKG WORK         firmware/examples/triangle-wave configured as
#                                 a project of its own in WORK against PKG (the
#                                 build tree, MODE=build, or an install prefix,
#                                 MODE=install), built, and its ctest run:
#                                 chainsim test on its test file, JUnit checked
#   example-pic MODE PKG WORK [over-limit]
#                                 the same project with -DCHAINSIM_PIC=ON: the
#                                 .hex and its size report; with over-limit, a
#                                 program too big for the part fails to build,
#                                 leaving no .hex. Exit 77 (SKIPPED) without
#                                 the toolchain.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../../.." && pwd)"
EXAMPLE="$ROOT/firmware/examples/triangle-wave"
fail() { echo "FAIL: $*" >&2; exit 1; }

package_args() { # MODE PKG
  case "$1" in
    build) echo "-Dchainsim_DIR=$2" ;;
    install) echo "-DCMAKE_PREFIX_PATH=$2" ;;
    *) fail "mode $1: build or install" ;;
  esac
}

case "${1:-}" in
  install)
    rm -rf "$3"
    cmake --install "$2" --prefix "$3" >"$3.log" 2>&1 || { cat "$3.log"; fail "cmake --install"; }
    for f in bin/chainsim bin/fw-central bin/fw-rotation lib/libchainsim_hal_sim.a lib/libchainsim_fw_common.a \
             include/chainsim/hal/hal.h include/chainsim/firmware/chain_app.h lib/cmake/chainsim/chainsimConfig.cmake \
             share/chainsim/scenes/default.yaml share/chainsim/scenes/modules/rotation.yaml \
             share/chainsim/pic/hal-pic/hal_time.c share/chainsim/pic/pic-toolchain.sh share/doc/chainsim/testing.md \
             share/chainsim/examples/triangle-wave/CMakeLists.txt; do
      [ -e "$3/$f" ] || fail "not installed: $f"
    done
    echo "installed into $3"
    ;;
  installed-run)
    prefix="$2" work="$3"
    rm -rf "$work" && mkdir -p "$work" && cd "$work"
    # a scene that loads mesh files next to it, and the built-in scene
    "$prefix/bin/chainsim" run "$prefix/share/chainsim/scenes/mesh-pipe.yaml" --duration 0.3 --out mesh -q ||
      fail "installed chainsim could not run mesh-pipe.yaml"
    "$prefix/bin/chainsim" run --duration 0.3 --out default -q || fail "installed chainsim could not run the built-in scene"
    grep -q '"exit_code": 0' mesh/summary.json default/summary.json || fail "no clean summary.json"
    grep -q '"program": "fw-central"' default/summary.json || fail "the central program did not run"
    # the viewer bundle comes from PREFIX/share/chainsim
    if [ -e "$prefix/share/chainsim/viewer.js" ]; then
      env -u CHAINSIM_VIEWER_DIR "$prefix/bin/chainsim" view default 2>view.err || { cat view.err; fail "chainsim view"; }
      grep -q "three" default/replay.html || fail "replay.html has no viewer bundle"
    fi
    echo "the installed chainsim runs from $work"
    ;;
  example|example-pic)
    mode="$2" pkg="$3" work="$4"
    args=$(package_args "$mode" "$pkg")
    if [ "$1" = example-pic ]; then
      cache="${CHAINSIM_PIC_CACHE:-$HOME/.cache/chainsim-pic}"
      [ -x "$cache/sdcc/bin/sdcc" ] && [ -f "$cache/rt/libsdcc.lib" ] ||
        { echo "SKIP: the PIC toolchain is not in $cache (tools/pic-toolchain.sh builds it)"; exit 77; }
      rm -rf "$work" && mkdir -p "$work"
      cmake -S "$EXAMPLE" -B "$work/build" $args -DCHAINSIM_PIC=ON >"$work/configure.log" 2>&1 ||
        { cat "$work/configure.log"; fail "configure with CHAINSIM_PIC=ON"; }
      cmake --build "$work/build" --target fw-triangle-wave-pic >"$work/build.log" 2>&1 ||
        { cat "$work/build.log"; fail "PIC build"; }
      [ -s "$work/build/fw-triangle-wave.hex" ] || fail "no fw-triangle-wave.hex"
      grep -q "^:00000001FF" "$work/build/fw-triangle-wave.hex" || fail "the .hex has no end record"
      grep "fw-triangle-wave.hex: flash" "$work/build/fw-triangle-wave.size" || fail "no size report"
      if [ "${5:-}" != over-limit ]; then
        echo "cross-built for the PIC against $mode $pkg"
        exit 0
      fi
      # a program over the part's 32 KB of flash does not build
      mkdir -p "$work/big"
      cat >"$work/big/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.22)
project(big LANGUAGES C)
find_package(chainsim REQUIRED)
chainsim_add_firmware(fw-big big.c)
CMAKE
      python3 - "$work/big/big.c" <<'PY'
import sys
text = "".join(chr(ord("a") + i % 26) for i in range(17000))
open(sys.argv[1], "w").write(
    '#include "hal.h"\n'
    'const hal_param_decl hal_param_table[] = { HAL_PARAM_END }; /* no parameters */\n'
    '/* 34 KB of text: more than the part\'s 32 KB of flash */\n'
    'static const char a[] = "%s";\nstatic const char b[] = "%s";\n'
    'int main(void)\n{\n    uint16_t i = 0;\n    hal_init();\n    for (;;) {\n'
    '        setspangle(0, (int16_t)(a[i] + b[i]));\n        i = (uint16_t)((i + 1u) %% 17000u);\n'
    '        hal_tick_wait();\n    }\n}\n' % (text, text))
PY
      cmake -S "$work/big" -B "$work/big/build" $args -DCHAINSIM_PIC=ON >/dev/null 2>&1 || fail "configure the big program"
      if cmake --build "$work/big/build" --target fw-big-pic >"$work/big.log" 2>&1; then
        fail "a program of 34 KB of text built for a 32 KB part"
      fi
      grep -q "No target memory available" "$work/big.log" || { cat "$work/big.log"; fail "no reason given"; }
      [ ! -e "$work/big/build/fw-big.hex" ] || fail "a .hex was left behind"
      echo "cross-built for the PIC; the program over the limits failed: $(grep -m1 'No target memory' "$work/big.log")"
    else
      rm -rf "$work" && mkdir -p "$work"
      cmake -S "$EXAMPLE" -B "$work/build" $args >"$work/configure.log" 2>&1 ||
        { cat "$work/configure.log"; fail "configure"; }
      cmake --build "$work/build" >"$work/build.log" 2>&1 || { cat "$work/build.log"; fail "build"; }
      if grep -q "warning:" "$work/build.log"; then cat "$work/build.log"; fail "the example compiles with warnings"; fi
      (cd "$work/build" && ctest --output-on-failure) || fail "the example's test failed"
      grep -q 'tests="1" failures="0" errors="0"' "$work/build/triangle-wave-crawl.junit.xml" || fail "JUnit report"
      grep -q '"program": ".*fw-triangle-wave"' "$work/build/triangle-wave-crawl-runs/triangle-wave-crawl-seed1/summary.json" ||
        fail "the run did not use the example's program"
      # a design search over the example's own program: --firmware-dir, program[...] targets
      chainsim_bin="$pkg/bin/chainsim"  # the build tree's or the prefix's
      [ -x "$chainsim_bin" ] || fail "no $chainsim_bin"
      (cd "$work/build" && "$chainsim_bin" optimize "$EXAMPLE/search.yaml" --out search --population 3 --generations 0 \
         --verify-top 0 --no-replay -q) 2>"$work/no-dir.txt" && fail "a search found fw-triangle-wave without --firmware-dir"
      grep -q "fw-triangle-wave" "$work/no-dir.txt" || { cat "$work/no-dir.txt"; fail "the missing program is not named"; }
      (cd "$work/build" && "$chainsim_bin" optimize "$EXAMPLE/search.yaml" --firmware-dir . --out search --population 3 \
         --generations 0 --workers 2 --verify-top 0 --no-replay -q) || fail "the search over the example's program"
      [ "$(wc -l <"$work/build/search/history.csv")" = 4 ] || { cat "$work/build/search/history.csv"; fail "3 individuals"; }
      grep -q "control_ms" "$work/build/search/best.yaml" || fail "best.yaml does not set control_ms"
      grep -q '"firmware_dir": "'"$work"'/build' "$work/build/search/search.json" || fail "search.json lacks the folder"
      echo "built and run against $mode $pkg"
    fi
    ;;
  *)
    sed -n '2,20p' "${BASH_SOURCE[0]}"
    exit 2
    ;;
esac
