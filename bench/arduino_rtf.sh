#!/usr/bin/env bash
# The Arduino layer's cost (issue 19): the obstacle avoider as C on the HAL
# (firmware_examples/avoider) and as an Arduino sketch on hal/arduino
# (firmware_examples/arduino/avoider_sketch), same room, same rover, same seed; and an HC-SR04
# pinged against a wall 1 m away, as C (firmware_examples/hcsr04_ping, the HAL's pulse_in) and as
# the pulseIn sketch (firmware_examples/arduino/sonar_sketch). Prints per firmware the median over
# RUNS runs of the stepping loop's wall-clock real-time factor (summary.json's real_time_factor)
# and the ratio sketch / C. Each firmware is built (and cached) by a first run.
# The timing loop is bench/timed_runs.sh's.
#
# Usage: bench/arduino_rtf.sh [path/to/sear]   (default: build-release/tools/sear, else build/tools/sear)
# Environment: RUNS (5), DURATION simulated seconds per run (20), ROOT the source tree.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=${ROOT:-$(dirname "$here")}
source "$here/timed_runs.sh"
sear=$(bench_sear arduino_rtf.sh "${1:-}")
RUNS=${RUNS:-5}
DURATION=${DURATION:-20}
work=$(mktemp -d /tmp/sear-arduino-rtf.XXXXXX)
trap 'rm -rf "$work"' EXIT

median_rtf() {
  local project=$1 name=$2
  bench_warm "$sear" "$work/$name-warm" "$project" --no-plots
  bench_runs "$sear" "$RUNS" "$DURATION" "$work/$name" "$project" --no-plots | bench_column 1 | bench_median
}

echo "load average at start: $(bench_load)"
c=$(median_rtf "$ROOT/firmware_examples/avoider/project.xml" c)
sketch=$(median_rtf "$ROOT/firmware_examples/arduino/avoider_sketch/project.xml" sketch)
printf 'avoider as C on the HAL      real-time factor %8.1f\n' "$c"
printf 'avoider as an Arduino sketch real-time factor %8.1f   (sketch / C = %.2f)\n' "$sketch" \
  "$(python3 -c "print($sketch / $c)")"
ping_c=$(median_rtf "$ROOT/firmware_examples/hcsr04_ping/project.xml" ping-c)
ping_sketch=$(median_rtf "$ROOT/firmware_examples/arduino/sonar_sketch/project.xml" ping-sketch)
printf 'sonar as C (pulse_in)        real-time factor %8.1f\n' "$ping_c"
printf 'sonar as a sketch (pulseIn)  real-time factor %8.1f   (sketch / C = %.2f)\n' "$ping_sketch" \
  "$(python3 -c "print($ping_sketch / $ping_c)")"
echo "load average at end: $(bench_load)"
