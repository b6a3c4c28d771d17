#!/usr/bin/env bash
# The AVR engine against the native one on the same project: runs the obstacle avoider
# (assets/projects/avoider_hills.xml) with `sear run --engine native` and `--engine avr`, and
# prints per engine the median over RUNS runs of the stepping loop's wall-clock real-time factor
# (summary.json's real_time_factor) and, for the AVR engine, the simulated MHz per host second
# (RTF x the MCU's clock: the avoider's ATmega2560 runs at 16 MHz) and its CPU load as the engine
# measured it (summary.json's avr_engines). Target (issue 20): at least 4x real time at 16 MHz.
# The wall-clock figures follow the host's load (printed beside them); the host CPU seconds the run
# took (sear and its MCU processes, user + system, mean per run) do much less, and give for the AVR engine
# the simulated MHz per host CPU second.
# Last, simavr on its own (bench/simavr_bare_bench: avr_run() on the avoider's AVR image from the
# build, no lockstep, no devices), median of RUNS runs of DURATION simulated seconds: what this
# host gives simavr's decoder at the moment, and the engine's simulated MHz per second as a share
# of it, which the host's speed changes much less than either figure.
# The timing loop is bench/timed_runs.sh's.
#
# Usage: bench/avr_engine_rtf.sh [path/to/sear]   (default: build-release/tools/sear, else build/tools/sear)
# Environment: RUNS (5), DURATION simulated seconds per run (20), ROOT the source tree.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=${ROOT:-$(dirname "$here")}
source "$here/timed_runs.sh"
sear=$(bench_sear avr_engine_rtf.sh "${1:-}")
RUNS=${RUNS:-5}
DURATION=${DURATION:-20}
work=$(mktemp -d /tmp/sear-avr-rtf.XXXXXX)
trap 'rm -rf "$work"' EXIT
project=$ROOT/assets/projects/avoider_hills.xml

printf '%-8s %10s %14s %8s %16s %10s %8s\n' engine rtf sim_MHz/s cpu_s sim_MHz/cpu_s cpu_load load
for engine in native avr; do
  load=$(bench_load | cut -d' ' -f1)
  bench_warm "$sear" "$work/$engine-warm" "$project" --engine "$engine" --no-plots
  # bash's times: the CPU seconds of the children waited for so far (sear reaps its MCUs).
  times >"$work/times"
  before=$(tail -1 "$work/times")
  rtf=$(bench_runs "$sear" "$RUNS" "$DURATION" "$work/$engine" "$project" --engine "$engine" --no-plots |
    bench_column 1 | bench_median)
  times >"$work/times"
  after=$(tail -1 "$work/times")
  cpu_s=$(awk -v b="$before" -v a="$after" -v n="$RUNS" 'function s(t) { sub("s$", "", t); split(t, p, "m"); return p[1] * 60 + p[2] }
    BEGIN { split(b, x, " "); split(a, y, " "); printf "%.3f\n", (s(y[1]) + s(y[2]) - s(x[1]) - s(x[2])) / n }')
  if [[ $engine == avr ]]; then
    mhz=$(awk -v r="$rtf" 'BEGIN {printf "%.1f", r * 16}')
    mhz_cpu=$(awk -v c="$cpu_s" -v d="$DURATION" 'BEGIN {printf "%.1f", (c > 0 ? 16 * d / c : 0)}')
    cpu=$(python3 -c 'import json, sys; print("%.3f" % json.load(open(sys.argv[1]))["avr_engines"]["rover.main"]["cpu_load"])' \
      "$work/avr.1/summary.json")
  else
    mhz=-
    mhz_cpu=-
    cpu=-
  fi
  printf '%-8s %10.2f %14s %8s %16s %10s %8s\n' "$engine" "$rtf" "$mhz" "$cpu_s" "$mhz_cpu" "$cpu" "$load"
done
bare=$(dirname "$sear")/../bench/simavr_bare_bench
image=$(dirname "$sear")/../avr/firmware_examples/avoider.elf
if [[ -x $bare && -f $image ]]; then
  load=$(bench_load | cut -d' ' -f1)
  bare_mhz=$(for ((i = 0; i < RUNS; ++i)); do "$bare" "$image" "$((DURATION * 16000000))" | tail -1; done | bench_median)
  printf '%-8s %10s %14s %8s %16s %10s %8s\n' simavr - "$bare_mhz" - - - "$load"
  awk -v e="$mhz" -v b="$bare_mhz" 'BEGIN { if (b > 0) printf "the AVR engine runs at %.2f times simavr'"'"'s own speed\n", e / b }'
else
  echo "(no $bare or $image: simavr on its own not measured)"
fi
