#!/usr/bin/env bash
# The Arduino layer's cost (issue 19): the obstacle avoider as C on the HAL
# (firmware_examples/avoider) and as an Arduino sketch on hal/arduino
# (firmware_examples/arduino/avoider_sketch), same room, same rover, same seed; prints per firmware
# the median over RUNS runs of the stepping loop's wall-clock real-time factor (summary.json's
# real_time_factor) and the ratio sketch / C. Both firmware are built (and cached) by a first run.
#
# Usage: bench/arduino_rtf.sh [path/to/sear]   (default: build-release/tools/sear, else build/tools/sear)
# Environment: RUNS (5), DURATION simulated seconds per run (20), ROOT the source tree.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=${ROOT:-$(dirname "$here")}
sear=${1:-}
if [[ -z $sear ]]; then
  for candidate in "$ROOT/build-release/tools/sear" "$ROOT/build/tools/sear"; do
    [[ -x $candidate ]] && { sear=$candidate; break; }
  done
fi
[[ -x ${sear:-} ]] || { echo "arduino_rtf.sh: no sear binary (give its path)" >&2; exit 2; }
RUNS=${RUNS:-5}
DURATION=${DURATION:-20}
work=$(mktemp -d /tmp/sear-arduino-rtf.XXXXXX)
trap 'rm -rf "$work"' EXIT

median_rtf() {
  local project=$1 name=$2
  SEAR_NO_PLOTS=1 "$sear" run "$project" -o "$work/$name-warm" --duration 0.1 >/dev/null
  for ((i = 0; i < RUNS; i++)); do
    SEAR_NO_PLOTS=1 "$sear" run "$project" -o "$work/$name-$i" --duration "$DURATION" >/dev/null
    python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["real_time_factor"])' "$work/$name-$i/summary.json"
  done | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'
}

c=$(median_rtf "$ROOT/firmware_examples/avoider/project.xml" c)
sketch=$(median_rtf "$ROOT/firmware_examples/arduino/avoider_sketch/project.xml" sketch)
printf 'avoider as C on the HAL      real-time factor %8.1f\n' "$c"
printf 'avoider as an Arduino sketch real-time factor %8.1f   (sketch / C = %.2f)\n' "$sketch" \
  "$(python3 -c "print($sketch / $c)")"
