#!/usr/bin/env bash
# Fingerprint of what chainsim produces, to prove that a refactor kept
# behaviour: every shipped scene's trace and bus log, the modules' logs, the
# servo bench's output, a bench and a robot calibration's reports and a
# small design search's history, as sha256 lines.
#
#   tools/behaviour-check.sh record FILE    write the fingerprint to FILE
#   tools/behaviour-check.sh compare FILE   fingerprint again, diff against FILE
#
# Uses build/bin/chainsim as built; wall-clock fields are left out of the
# calibration reports. Takes a few minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-}"
file="${2:-}"
if [[ "$mode" != record && "$mode" != compare || -z "$file" ]]; then
  echo "usage: $0 record|compare FILE" >&2
  exit 1
fi
bin=build/bin/chainsim
[[ -x $bin ]] || { echo "behaviour-check: $bin not built" >&2; exit 1; }
work=$(mktemp -d /tmp/chainsim-fingerprint-XXXXXX)
trap 'rm -rf "$work"' EXIT
out="$work/fingerprint.txt"
: >"$out"

sha() { sha256sum "$1" | cut -d' ' -f1; }
# json without the keys that hold wall-clock time
json_sha() {
  [[ -f $1 ]] || { echo "missing"; return; }
  python3 - "$1" <<'EOF' | sha256sum | cut -d' ' -f1
import json, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if 'wall' not in k and k not in ('pid', 'real_time_factor')}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
print(json.dumps(strip(json.load(open(sys.argv[1]))), sort_keys=True))
EOF
}

# every shipped scene: 2 at a time
scenes=(scenes/*.yaml)
run_one() {
  local s="$1" name dir
  name=$(basename "$s" .yaml)
  dir="$work/run-$name"
  "$bin" run "$s" --out "$dir" --quiet >"$work/$name.stdout" 2>&1 || true
}
export -f run_one
export bin work
printf '%s\n' "${scenes[@]}" | xargs -P 2 -I{} bash -c 'run_one "$@"' _ {}
for s in "${scenes[@]}"; do
  name=$(basename "$s" .yaml)
  dir="$work/run-$name"
  if [[ ! -f $dir/summary.json ]]; then
    echo "scene $name: no summary.json ($(tail -n 2 "$work/$name.stdout"))" >>"$out"
    continue
  fi
  echo "scene $name trace_sha256 $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["trace_sha256"])' "$dir/summary.json")" >>"$out"
  echo "scene $name summary $(json_sha "$dir/summary.json")" >>"$out"
  echo "scene $name bus.log $(sha "$dir/bus.log")" >>"$out"
  for l in "$dir"/modules/*.log; do
    echo "scene $name $(basename "$l") $(sha "$l")" >>"$out"
  done
done

# the servo bench, plain and with an effect switched on
"$bin" bench --bench scenes/bench/servo-default.yaml --setpoints scenes/bench/step-30-120.csv \
  --out "$work/bench.csv" >/dev/null 2>&1
echo "bench servo-default $(sha "$work/bench.csv")" >>"$out"
sed 's/^  i_threshold_a: 0.0 /  backlash_deg: 3.0\n  i_threshold_a: 0.0 /' scenes/bench/servo-default.yaml >"$work/bench-backlash.yaml"
"$bin" bench --bench "$work/bench-backlash.yaml" --setpoints scenes/bench/step-30-120.csv \
  --out "$work/bench-backlash.csv" >/dev/null 2>&1
echo "bench servo-backlash $(sha "$work/bench-backlash.csv")" >>"$out"

# calibration of the backlash bench output against the plain bench file
"$bin" calibrate --bench scenes/bench/servo-default.yaml --measured "$work/bench-backlash.csv" \
  --out "$work/cal" --quiet >/dev/null 2>&1 || true
echo "calibrate bench report.json $(json_sha "$work/cal/report.json")" >>"$out"
for f in angle.svg residual.svg current.svg; do
  [[ -f $work/cal/$f ]] && echo "calibrate bench $f $(sha "$work/cal/$f")" >>"$out"
done

# robot-level calibration against the paper's Table 2 (short runs)
"$bin" calibrate --robot scenes/measured/helicoidal_speed_vs_slope.csv \
  --scene-template 'scenes/helicoidal-{slope}.yaml' --duration 2.5 --out "$work/robot" --quiet \
  >/dev/null 2>&1 || true
echo "calibrate robot report.json $(json_sha "$work/robot/report.json")" >>"$out"

# a shipped problem's design search, a small one (4 individuals, 1 generation,
# 3 trials each): its history without the wall-clock column
"$bin" optimize scenes/optimize/terrain-gait.yaml --population 4 --generations 1 --workers 2 \
  --verify-top 0 --no-replay --out "$work/opt" --quiet >/dev/null 2>&1 || true
if [[ -f $work/opt/history.csv ]]; then
  echo "optimize terrain-gait history $(python3 -c '
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
w = rows[0].index("wall_s")
print("\n".join(",".join(c for i, c in enumerate(r) if i != w) for r in rows))' "$work/opt/history.csv" | sha256sum | cut -d' ' -f1)" >>"$out"
else
  echo "optimize terrain-gait history missing" >>"$out"
fi

if [[ $mode == record ]]; then
  cp "$out" "$file"
  echo "behaviour-check: $(wc -l <"$file") fingerprints written to $file"
else
  if diff -u "$file" "$out"; then
    echo "behaviour-check: identical ($(wc -l <"$file") fingerprints)"
  else
    echo "behaviour-check: DIFFERENT from $file" >&2
    exit 1
  fi
fi
