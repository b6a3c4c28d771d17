#!/usr/bin/env bash
# What a step costs the simulator's process, in instructions (callgrind), per part of the step:
# a count the host's speed does not move, where the real-time factors of one binary spread by
# ±15 % from set to set on these shared machines. Per scenario and sear binary: the whole step
# (Lockstep::step), ODE's step, what comes before the firmware's quantum (the sensors' truth and
# the serial lines, McuBridge::begin_quantum) and its biggest parts (the HC-SR04's cone, the bump
# lever, the serial exchange), the capture (McuCapture::advance_to) and what comes after the
# quantum (McuBridge::finish_quantum, the firmware's events and readings; its waits spin, so this
# part moves a little with the host). Scenarios:
#   default   the reference rover (assets/projects/default.xml)
#   nolidar   the same without its LMS200
#   avoider   the obstacle avoider (assets/projects/avoider_hills.xml)
# The firmware runs natively beside valgrind (--trace-children=no): only the simulator is counted.
#
# Usage: bench/step_instructions.sh [SEAR...]   (default: build-release/tools/sear, else build/tools/sear)
# Environment: DURATION simulated seconds per run (10; the LMS200 streams from 2 s on),
#   SCENARIOS (all, in the order above), ROOT the source tree whose projects to use.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=${ROOT:-$(dirname "$here")}
source "$here/timed_runs.sh"
command -v valgrind >/dev/null && command -v callgrind_annotate >/dev/null ||
  { echo "step_instructions.sh: valgrind (Debian package valgrind) is missing" >&2; exit 2; }
binaries=("$@")
((${#binaries[@]})) || binaries=("$(bench_sear step_instructions.sh)")
for b in "${binaries[@]}"; do [[ -x $b ]] || { echo "step_instructions.sh: $b is not executable" >&2; exit 2; }; done
DURATION=${DURATION:-10}
SCENARIOS=${SCENARIOS:-"default nolidar avoider"}

work=$(mktemp -d /tmp/sear-step-instructions.XXXXXX)
trap 'rm -rf "$work"' EXIT
bench_nolidar_project >"$work/nolidar.xml"

# The parts, as callgrind_annotate names the functions, and their columns' headings.
parts=("sear::Lockstep::step(" "sear::Simulation::step()" "sear::McuBridge::begin_quantum(" "Hcsr04::sample("
  "BumpSwitch::sample(" "sear::McuBridge::exchange_serial(" "sear::McuCapture::advance_to(" "sear::McuBridge::finish_quantum(")
echo "instructions a step (thousands), $DURATION s simulated a run; $(date -u '+%F %T') UTC"
for i in "${!binaries[@]}"; do echo "sear $((i + 1)): ${binaries[$i]}"; done
printf '%-8s %4s %7s %7s %7s %7s %7s %7s %7s %7s\n' scenario sear step physics before sonar bump serial capture after
for s in $SCENARIOS; do
  case $s in
    default) project=$ROOT/assets/projects/default.xml ;;
    nolidar) project=$work/nolidar.xml ;;
    avoider) project=$ROOT/assets/projects/avoider_hills.xml ;;
    *) echo "step_instructions.sh: unknown scenario '$s'" >&2; exit 2 ;;
  esac
  for b in "${!binaries[@]}"; do
    out=$work/$s.$b
    mkdir -p "$out"
    bench_warm "${binaries[$b]}" "$out/warm" "$project"
    SEAR_NO_PLOTS=1 valgrind --tool=callgrind --trace-children=no --callgrind-out-file="$out/cg.%p" \
      "${binaries[$b]}" run "$project" --duration "$DURATION" --quiet --no-plots -o "$out/run" >"$out/log" 2>&1 ||
      { echo "step_instructions.sh: $s with ${binaries[$b]} failed:" >&2; tail -n 5 "$out/log" >&2; exit 1; }
    steps=$(jq -r .steps "$out/run/summary.json")
    # The simulator's own file is the largest: the firmware's fork is counted only until its exec.
    annotated=$(callgrind_annotate --inclusive=yes --threshold=100 "$(ls -S "$out"/cg.* | head -n 1)" 2>/dev/null)
    row=()
    for p in "${parts[@]}"; do
      # A part the scenario lacks (the avoider has no sonar) is 0.
      n=$(grep -F "$p" <<<"$annotated" | grep -v '=>' | grep -F '[' | head -n 1 | awk '{ gsub(",", "", $1); print $1 }') || n=0
      row+=("$(awk -v n="${n:-0}" -v k="$steps" 'BEGIN { printf "%.1f", n / k / 1000 }')")
    done
    printf '%-8s %4s %7s %7s %7s %7s %7s %7s %7s %7s\n' "$s" "$((b + 1))" "${row[@]}"
  done
done
