#!/usr/bin/env bash
# Whole-run real-time factor: what a user waits for. Runs `sear run` on
#   default  the bundled default project: the reference rover, every sensor kind on one MCU
#   onecore  the same with the simulator and its firmware sharing one core (taskset -c 0)
#   nolidar  the reference rover without its LMS200 (its firmware then asks a scanner nobody answers)
#   avoider  the default world with the obstacle avoider's rover (assets/projects/avoider_hills.xml)
#   busy     the avoider beside one busy host process (`sh -c 'while :; do :; done'`, killed afterwards)
#   two      two avoider rovers, each with its own MCU (bench/projects/avoider_two.xml)
#   eight    eight such rovers (bench/projects/avoider_eight.xml)
#   forest   the reference rover among 400 more obstacles, a third of them loose: what a crowded
#            world costs beyond the default one (not run unless named in SCENARIOS)
#   lcm      the default project publishing everything on LCM (`--lcm`, default 100 Hz), each run in
#            its own private network namespace (unshare -n, root) with multicast on its loopback;
#            compare its loop RTF with default's: the target is a cost under 10 %
# and prints, per scenario, the median over RUNS runs of the wall-clock real-time factor of the
# stepping loop (summary.json's real_time_factor: simulated seconds per wall second, from the first
# step to the last) and of the whole process (start-up, firmware from cache and loading included),
# with the load average when the scenario started. The timing loop is bench/timed_runs.sh's.
#
# Usage: bench/run_rtf.sh [path/to/sear]        (default: build-release/tools/sear, else build/tools/sear)
# Environment: RUNS (3), DURATION simulated seconds per run (20), SCENARIOS ("default busy two eight"),
#   LOCK the build lock taken around each scenario so that builds do not share the cores with a
#   measurement (/tmp/sear-build.lock; empty: none), ROOT the source tree whose assets to use.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=${ROOT:-$(dirname "$here")}
source "$here/timed_runs.sh"
sear=$(bench_sear run_rtf.sh "${1:-}")
RUNS=${RUNS:-3}
DURATION=${DURATION:-20}
SCENARIOS=${SCENARIOS:-"default onecore nolidar avoider busy two eight"}
LOCK=${LOCK-/tmp/sear-build.lock}

work=$(mktemp -d /tmp/sear-rtf.XXXXXX)
busy_pid=
cleanup() {
  [[ -n $busy_pid ]] && kill "$busy_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# A bundled project with its relative paths made absolute, so that copies of it can live in $work.
absolute_project() { bench_absolute_paths <"$ROOT/assets/projects/$1.xml"; }

run_scenario() {
  local name=$1 project=$2
  local load extra=()
  BENCH_PREFIX=()
  [[ $name == onecore ]] && BENCH_PREFIX=(taskset -c 0)
  [[ $name == lcm ]] && extra=(--lcm) && BENCH_PREFIX=(unshare -n sh -c \
    'ip link set lo up && ip link set lo multicast on && ip route add 239.0.0.0/8 dev lo && exec "$@"' sh)
  bench_warm "$sear" "$work/warm" "$project"
  if [[ $name == busy ]]; then
    sh -c 'while :; do :; done' &
    busy_pid=$!
    sleep 0.5
  fi
  load=$(bench_load)
  bench_runs "$sear" "$RUNS" "$DURATION" "$work/$name" "$project" "${extra[@]}" >"$work/$name.runs"
  BENCH_PREFIX=()
  if [[ -n $busy_pid ]]; then
    kill "$busy_pid"
    wait "$busy_pid" 2>/dev/null || true
    busy_pid=
  fi
  # Per run: loop RTF, whole seconds, simulated seconds (bench_runs); the whole RTF is sim / whole.
  printf '%-8s %6s %10.1f %10.1f   %s   [%s]\n' "$name" "$RUNS" \
    "$(bench_column 1 <"$work/$name.runs" | bench_median)" "$(awk '{ print $3 / $2 }' "$work/$name.runs" | bench_median)" \
    "$load" "$(bench_column 1 <"$work/$name.runs" | xargs printf '%.1f ')"
}

absolute_project default >"$work/default.xml"
grep -v "<lms2xx" "$work/default.xml" >"$work/nolidar.xml"
absolute_project avoider_hills >"$work/avoider.xml"
bench_forest_project >"$work/forest.xml"

echo "sear: $sear; $DURATION s simulated per run; $(nproc) cores; $(date -u '+%F %T') UTC"
printf '%-8s %6s %10s %10s   %s   %s\n' scenario runs "loop RTF" "whole RTF" "load avg (1/5/15 min) at start" "[each run's loop RTF]"
for s in $SCENARIOS; do
  case $s in
    default | onecore | lcm) project="$work/default.xml" ;;
    nolidar) project="$work/nolidar.xml" ;;
    avoider | busy) project="$work/avoider.xml" ;;
    two) project="$here/projects/avoider_two.xml" ;;
    eight) project="$here/projects/avoider_eight.xml" ;;
    forest) project="$work/forest.xml" ;;
    *) echo "run_rtf.sh: unknown scenario '$s'" >&2; exit 2 ;;
  esac
  if [[ -n $LOCK ]]; then
    exec 9>"$LOCK"
    flock 9
    run_scenario "$s" "$project"
    flock -u 9
    exec 9>&-
  else
    run_scenario "$s" "$project"
  fi
done
