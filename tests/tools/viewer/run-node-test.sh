#!/usr/bin/env bash
# Runs one viewer test file with Node's test runner. Exits 77 (ctest: SKIPPED,
# with the reason printed) when what the viewer tests need is not installed:
# node, Chromium (Debian package chromium) or the viewer's npm packages.
set -uo pipefail
test_file="$1"
skip() { echo "SKIP: $*"; exit 77; }
command -v node >/dev/null 2>&1 || skip "node is not installed (Debian package nodejs)"
chromium="${CHAINSIM_CHROMIUM:-/usr/bin/chromium}"
[ -x "$chromium" ] || skip "Chromium is not installed at $chromium (Debian package chromium)"
[ -n "${VIEWER_NODE_MODULES:-}" ] && [ -d "$VIEWER_NODE_MODULES/playwright-core" ] ||
  skip "playwright-core is not installed (npm ci of tools/viewer did not run: needs npm at configure time)"
[ -x "${CHAINSIM_EXE:-}" ] || { echo "FAIL: chainsim not built at ${CHAINSIM_EXE:-?}"; exit 1; }
exec node --test --test-reporter=spec "$test_file"
