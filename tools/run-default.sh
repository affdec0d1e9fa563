#!/usr/bin/env bash
# Set up (packages, build) and run the built-in default scene: a snake of eight
# rotation modules crawling in open air. Extra arguments go to `chainsim run`.
set -euo pipefail
cd "$(dirname "$0")/.."
SETUP_PACKAGES=run SETUP_TARGET=chainsim-tools tools/setup.sh  # chainsim, its evaluator and the programs: no test binaries, no test tools
exec build/bin/chainsim run "$@"
