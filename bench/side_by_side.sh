#!/usr/bin/env bash
# Speed of whole runs, in one table (issue 23): per scenario and sear binary, the median over RUNS
# runs of the stepping loop's real-time factor and of the whole run's wall time (`time sear run`:
# start-up, firmware from the cache, plots included as sear draws them), with the time outside the
# loop, the seconds its plots took after the exit (drawn in the background), whether the whole
# run kept within issue 23's bound of 1.15 x the loop's time + 0.5 s, and the microseconds a step
# spent before the firmware's quantum, in the capture, in physics and after the quantum
# (summary.json's step_wall_us, "-" from a sear without it). Scenarios:
#   default   the reference rover (assets/projects/default.xml), every sensor kind on one MCU
#   avoider   the obstacle avoider (assets/projects/avoider_hills.xml)
#   two       two avoider rovers, an MCU each (bench/projects/avoider_two.xml)
#   eight     eight of them (bench/projects/avoider_eight.xml)
#   nolidar   the reference rover without its LMS200
#   forest    the reference rover among 400 more obstacles, a third of them loose (not by default)
#   noplots   the reference rover with --no-plots
#   short     the reference rover for 1 s: the start-up (target: under 0.3 s outside the loop)
# Given several binaries (an old and a new build), their runs alternate, run by run, so that they
# share whatever load the host has; the load average is printed per scenario and at the end.
#
# Usage: bench/side_by_side.sh [SEAR...]   (default: build-release/tools/sear, else build/tools/sear)
# Environment: RUNS (5), DURATION simulated seconds per run (60), SCENARIOS (all, in the order
#   above), ROOT the source tree whose projects to use.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=${ROOT:-$(dirname "$here")}
source "$here/timed_runs.sh"
binaries=("$@")
((${#binaries[@]})) || binaries=("$(bench_sear side_by_side.sh)")
for b in "${binaries[@]}"; do [[ -x $b ]] || { echo "side_by_side.sh: $b is not executable" >&2; exit 2; }; done
RUNS=${RUNS:-5}
DURATION=${DURATION:-60}
SCENARIOS=${SCENARIOS:-"default avoider two eight nolidar noplots short"}

work=$(mktemp -d /tmp/sear-side-by-side.XXXXXX)
trap 'rm -rf "$work"' EXIT
bench_nolidar_project >"$work/nolidar.xml"
bench_forest_project >"$work/forest.xml"

echo "$RUNS runs per line (medians), $DURATION s simulated (short: 1 s); $(nproc) cores; $(date -u '+%F %T') UTC"
for i in "${!binaries[@]}"; do echo "sear $((i + 1)): ${binaries[$i]}"; done
printf '%-8s %4s %9s %9s %9s %9s %9s %6s %23s   %s\n' scenario sear "loop RTF" "loop s" "whole s" "outside" "plots s" \
  bound "step us: pre cap phy post" "load avg at start (1/5/15 min)"
for s in $SCENARIOS; do
  args=() duration=$DURATION
  case $s in
    default) project=$ROOT/assets/projects/default.xml ;;
    avoider) project=$ROOT/assets/projects/avoider_hills.xml ;;
    two) project=$here/projects/avoider_two.xml ;;
    eight) project=$here/projects/avoider_eight.xml ;;
    nolidar) project=$work/nolidar.xml ;;
    forest) project=$work/forest.xml ;;
    noplots) project=$ROOT/assets/projects/default.xml args=(--no-plots) ;;
    short) project=$ROOT/assets/projects/default.xml duration=1 ;;
    *) echo "side_by_side.sh: unknown scenario '$s'" >&2; exit 2 ;;
  esac
  load=$(bench_load)
  for b in "${!binaries[@]}"; do bench_warm "${binaries[$b]}" "$work/warm.$b" "$project" "${args[@]}"; done
  for ((run = 1; run <= RUNS; ++run)); do
    for b in "${!binaries[@]}"; do
      bench_runs "${binaries[$b]}" 1 "$duration" "$work/$s.$b.$run" "$project" "${args[@]}" >>"$work/$s.$b"
      rm -rf "$work/$s.$b.$run.1"
    done
  done
  for b in "${!binaries[@]}"; do
    # Per run: loop RTF, whole s, sim s, plots s; the loop's seconds are sim / RTF.
    rtf=$(bench_column 1 <"$work/$s.$b" | bench_median)
    whole=$(bench_column 2 <"$work/$s.$b" | bench_median)
    loop=$(awk '{ print $3 / $1 }' "$work/$s.$b" | bench_median)
    outside=$(awk '{ print $2 - $3 / $1 }' "$work/$s.$b" | bench_median)
    plots=$(bench_column 4 <"$work/$s.$b" | bench_median)
    bound=$(awk -v w="$whole" -v l="$loop" 'BEGIN { print (w <= 1.15 * l + 0.5) ? "ok" : "over" }')
    # Where a step's wall time went (summary.json's step_wall_us), medians: a change's share of a
    # step moves far less with the host's speed than the real-time factor does.
    parts=""
    for column in 5 6 7 8; do
      values=$(bench_column "$column" <"$work/$s.$b" | awk '$1 != "-"')
      if [[ -n $values ]]; then parts+=$(printf ' %5.1f' "$(bench_median <<<"$values")"); else parts+='     -'; fi
    done
    printf '%-8s %4s %9.1f %9.2f %9.2f %9.2f %9.2f %6s %23s   %s\n' "$s" "$((b + 1))" "$rtf" "$loop" "$whole" "$outside" \
      "$plots" "$bound" "$parts" "$load"
  done
done
echo "load avg at the end: $(bench_load)"
