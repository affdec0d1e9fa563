#!/usr/bin/env bash
# The design search's farm against its ceiling: the same simulations as K
# independent `chainsim run`s side by side on this machine.
#
#   tools/bench-farm.sh PROBLEM.yaml K [chainsim optimize options...]
#
# 1. `chainsim optimize PROBLEM --workers K --keep-runs --verify-top 0
#    --no-replay` with the options given (e.g. --population 12
#    --generations 0): its wall time, and every scene it simulated;
# 2. those scenes again, K at a time (xargs -P K), each run by
#    chainsim-evaluate (the `chainsim run` the search uses, without its
#    pagmo and OpenMPI start-up): the ceiling, with no search around them.
# Prints simulations per minute of each and their ratio (the farm's
# efficiency; docs/benchmarks.md). Uses build/bin/chainsim as built.
set -euo pipefail
cd "$(dirname "$0")/.."
[[ $# -ge 2 ]] || { echo "usage: $0 PROBLEM.yaml K [chainsim optimize options...]" >&2; exit 1; }
problem=$1
k=$2
shift 2
bin=$PWD/build/bin/chainsim
[[ -x $bin ]] || { echo "bench-farm: $bin not built" >&2; exit 1; }
work=$(mktemp -d /tmp/chainsim-bench-farm-XXXXXX)
trap 'rm -rf "$work"' EXIT

now() { date +%s.%N; }
t0=$(now)
"$bin" optimize "$problem" --out "$work/search" --workers "$k" --keep-runs --verify-top 0 --no-replay -q "$@"
t1=$(now)
find "$work/search/work" -name 'scene*.yaml' | sort >"$work/scenes.txt"
n=$(wc -l <"$work/scenes.txt")
[[ $n -gt 0 ]] || { echo "bench-farm: the search simulated nothing" >&2; exit 1; }
t2=$(now)
i=0
while read -r s; do
  i=$((i + 1))
  echo "$s $work/runs/$i"
done <"$work/scenes.txt" | xargs -P "$k" -n 2 sh -c '"$0" "$1" "$2" 60 >/dev/null 2>&1 || true' "$bin-evaluate"  # a run that faults is a result, as in the search
t3=$(now)
python3 - "$n" "$k" "$t0" "$t1" "$t2" "$t3" <<'PY'
import sys
n, k = int(sys.argv[1]), int(sys.argv[2])
t0, t1, t2, t3 = map(float, sys.argv[3:])
search, alone = t1 - t0, t3 - t2
print(f"# {n} simulations, {k} at a time")
print(f"{'mode':<34}{'wall_s':>9}{'sims/min':>10}")
print(f"{'chainsim optimize --workers ' + str(k):<34}{search:9.1f}{60 * n / search:10.1f}")
print(f"{str(k) + ' chainsim runs side by side':<34}{alone:9.1f}{60 * n / alone:10.1f}")
print(f"efficiency (ceiling / search wall): {alone / search:.3f}")
PY
