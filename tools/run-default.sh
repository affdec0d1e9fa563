#!/usr/bin/env bash
# Set up (packages, build) and run the built-in default scene: a snake of eight
# rotation modules crawling in open air. Extra arguments go to `chainsim run`.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
exec build/bin/chainsim run "$@"
