#!/usr/bin/env bash
# Whole-run real-time factor: what a user waits for. Runs `sear run` on
#   default  the bundled default project: the reference rover, every sensor kind on one MCU
#   onecore  the same with the simulator and its firmware sharing one core (taskset -c 0)
#   nolidar  the reference rover without its LMS200 (its firmware then asks a scanner nobody answers)
#   avoider  the default world with the obstacle avoider's rover (assets/projects/avoider_hills.xml)
#   busy     the avoider beside one busy host process (`sh -c 'while :; do :; done'`, killed afterwards)
#   two      two avoider rovers, each with its own MCU
#   eight    eight such rovers
#   lcm      the default project publishing everything on LCM (`--lcm`, default 100 Hz), each run in
#            its own private network namespace (unshare -n, root) with multicast on its loopback;
#            compare its loop RTF with default's: the target is a cost under 10 %
# and prints, per scenario, the median over RUNS runs of the wall-clock real-time factor of the
# stepping loop (summary.json's real_time_factor: simulated seconds per wall second, from the first
# step to the last) and of the whole process (start-up, firmware from cache and loading included),
# with the load average when the scenario started.
#
# Usage: bench/run_rtf.sh [path/to/sear]        (default: build-release/tools/sear, else build/tools/sear)
# Environment: RUNS (3), DURATION simulated seconds per run (20), SCENARIOS ("default busy two eight"),
#   LOCK the build lock taken around each scenario so that builds do not share the cores with a
#   measurement (/tmp/sear-build.lock; empty: none), ROOT the source tree whose assets to use.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=${ROOT:-$(dirname "$here")}
sear=${1:-}
if [[ -z $sear ]]; then
  for candidate in "$ROOT/build-release/tools/sear" "$ROOT/build/tools/sear"; do
    [[ -x $candidate ]] && { sear=$candidate; break; }
  done
fi
[[ -x ${sear:-} ]] || { echo "run_rtf.sh: no sear binary (give its path)" >&2; exit 2; }
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
absolute_project() {
  sed -e "s#\\([\" ]\\)\\.\\./\\.\\./#\\1$ROOT/#g" -e "s#\\([\" ]\\)\\.\\./#\\1$ROOT/assets/#g" "$ROOT/assets/projects/$1.xml"
}

# The default world with n rovers, each with the avoider rover's MCU (avoider and sensors), spread
# over open ground clear of the obstacles and of each other.
multi_robot_project() {
  local n=$1 out=$2
  local poses=("0 0 0" "0 -6 90" "-6 0 180" "6 6 -90" "-7 -7 45" "7 -9 135" "-8 7 -45" "9 1 200")
  ((n <= ${#poses[@]})) || { echo "run_rtf.sh: at most ${#poses[@]} robots" >&2; exit 2; }
  absolute_project avoider_hills | awk -v n="$n" -v poses="$(IFS=,; echo "${poses[*]}")" '
    BEGIN { split(poses, pose, ",") }
    /<robot / { inrobot = 1; robot = "" }
    inrobot { robot = robot $0 "\n"; if ($0 ~ /<\/robot>/) { inrobot = 0
        for (i = 1; i <= n; ++i) {
          split(pose[i], p, " ")
          r = robot
          sub(/<robot /, "<robot name=\"rover" i "\" ", r)
          sub(/<pose [^>]*>/, "<pose x=\"" p[1] "\" y=\"" p[2] "\" yaw_deg=\"" p[3] "\"/>", r)
          printf "%s", r
        }
      }
      next }
    { print }' >"$out"
}

median() { sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

run_scenario() {
  local name=$1 project=$2
  local loop_rtfs=() whole_rtfs=() load pin=()
  [[ $name == onecore ]] && pin=(taskset -c 0)
  local extra=()
  [[ $name == lcm ]] && extra=(--lcm) && pin=(unshare -n sh -c \
    'ip link set lo up && ip link set lo multicast on && ip route add 239.0.0.0/8 dev lo && exec "$@"' sh)
  # One run first, not counted: it compiles the firmware into the cache and warms the page cache.
  "$sear" run "$project" --duration 0.1 --quiet --out "$work/warm" >/dev/null 2>&1 || true
  if [[ $name == busy ]]; then
    sh -c 'while :; do :; done' &
    busy_pid=$!
    sleep 0.5
  fi
  load=$(cut -d' ' -f1-3 /proc/loadavg)
  for ((i = 0; i < RUNS; ++i)); do
    local out="$work/$name.$i" t0 t1
    t0=$(date +%s.%N)
    "${pin[@]}" "$sear" run "$project" --duration "$DURATION" --quiet --out "$out" "${extra[@]}" >/dev/null 2>"$work/err" ||
      { echo "run_rtf.sh: $name run $i failed:" >&2; cat "$work/err" >&2; exit 1; }
    t1=$(date +%s.%N)
    loop_rtfs+=("$(jq -r .real_time_factor "$out/summary.json")")
    whole_rtfs+=("$(jq -r --arg w "$(echo "$t1 - $t0" | bc -l)" '.sim_time_s / ($w | tonumber)' "$out/summary.json")")
  done
  if [[ -n $busy_pid ]]; then
    kill "$busy_pid"
    wait "$busy_pid" 2>/dev/null || true
    busy_pid=
  fi
  printf '%-8s %6s %10.1f %10.1f   %s   [%s]\n' "$name" "$RUNS" \
    "$(printf '%s\n' "${loop_rtfs[@]}" | median)" "$(printf '%s\n' "${whole_rtfs[@]}" | median)" "$load" \
    "$(printf '%.1f ' "${loop_rtfs[@]}")"
}

absolute_project default >"$work/default.xml"
grep -v "<lms2xx" "$work/default.xml" >"$work/nolidar.xml"
absolute_project avoider_hills >"$work/avoider.xml"
multi_robot_project 2 "$work/two.xml"
multi_robot_project 8 "$work/eight.xml"

echo "sear: $sear; $DURATION s simulated per run; $(nproc) cores; $(date -u '+%F %T') UTC"
printf '%-8s %6s %10s %10s   %s   %s\n' scenario runs "loop RTF" "whole RTF" "load avg (1/5/15 min) at start" "[each run's loop RTF]"
for s in $SCENARIOS; do
  case $s in
    default | onecore | lcm) project="$work/default.xml" ;;
    nolidar) project="$work/nolidar.xml" ;;
    avoider | busy) project="$work/avoider.xml" ;;
    two) project="$work/two.xml" ;;
    eight) project="$work/eight.xml" ;;
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
