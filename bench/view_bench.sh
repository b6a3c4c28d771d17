#!/usr/bin/env bash
# What the browser viewer costs a run: the bundled default project's loop real-time factor
# (summary.json's real_time_factor) run as fast as it goes
#   plain    without the viewer
#   idle     with `--view` and no page connected (the target: no cost)
#   watched  with `--view` and a page connected that reads every frame (python3-websocket; the
#            target: under 5 % below plain)
#   built    with `--view` and a page connected that never reads: frames are built at 20 Hz but
#            not sent (its socket full), which parts the run's own cost from the reading page's
#   replay   with `--replay FILE` (20 frames per simulated second into a gzip file)
# and prints the median over RUNS runs of each, with its cost against plain.
#
# Usage: bench/view_bench.sh [path/to/sear]     (default: build-release/tools/sear, else build/tools/sear)
# Environment: RUNS (5), DURATION simulated seconds per run (20), LOCK the build lock held while
#   measuring (/tmp/sear-build.lock; empty: none).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(dirname "$here")
sear=${1:-}
if [[ -z $sear ]]; then
  for candidate in "$ROOT/build-release/tools/sear" "$ROOT/build/tools/sear"; do
    [[ -x $candidate ]] && { sear=$candidate; break; }
  done
fi
[[ -x ${sear:-} ]] || { echo "view_bench.sh: no sear binary (give its path)" >&2; exit 2; }
RUNS=${RUNS:-5}
DURATION=${DURATION:-20}
LOCK=${LOCK-/tmp/sear-build.lock}
export SEAR_NO_PLOTS=1

work=$(mktemp -d /tmp/sear-view-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT

# A page that reads every message until the run closes the connection; it counts the frames.
# Started before the run, so that Python's start-up is not counted against it: it waits for the
# viewer's address in the run's stderr.
cat >"$work/page.py" <<'EOF'
import re, socket, sys, time, websocket
while True:
    m = re.search(r"viewer on http://([^/]+)/", open(sys.argv[1]).read())
    if m:
        break
    time.sleep(0.002)
small = ((socket.SOL_SOCKET, socket.SO_RCVBUF, 4096),) if len(sys.argv) > 2 else ()
# websocket-client checks UTF-8 in pure Python, ~4 ms a 13 kB frame: 11 % of a core at 30 frames a
# second, which a browser does natively. Skipped, so that the page's cost is the server's, not this script's.
ws = websocket.create_connection(f"ws://{m.group(1)}/ws", sockopt=small, skip_utf8_validation=True)
if len(sys.argv) > 2:  # never read: wait for the run to end
    while "viewer on" in open(sys.argv[1]).read() and not open(sys.argv[2]).read():
        time.sleep(0.05)
    sys.exit()
frames = 0
try:
    while True:
        frames += '"type":"frame"' in ws.recv()
except Exception:
    pass
print(frames)
EOF

median() { sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# One run of scenario $1 into $2; prints its loop RTF.
one_run() {
  local name=$1 out=$2 args=(run --duration "$DURATION" --quiet --out "$2")
  case $name in
    plain) "$sear" "${args[@]}" >/dev/null ;;
    idle) "$sear" "${args[@]}" --view --port 0 >/dev/null 2>"$work/err" ;;
    replay) "$sear" "${args[@]}" --replay "$out.gz" >/dev/null ;;
    watched | built)
      : >"$work/err"
      : >"$work/done"
      if [[ $name == watched ]]; then /usr/bin/python3 "$work/page.py" "$work/err" >"$work/frames" &
      else /usr/bin/python3 "$work/page.py" "$work/err" "$work/done" & fi
      local page=$!
      sleep 0.3  # its imports done
      "$sear" "${args[@]}" --view --port 0 >/dev/null 2>"$work/err"
      echo done >"$work/done"
      wait "$page"
      ;;
  esac
  jq -r .real_time_factor "$out/summary.json"
}

"$sear" run --duration 0.1 --quiet --out "$work/warm" >/dev/null 2>&1 || true  # firmware into the cache
[[ -n $LOCK ]] && { exec 9>"$LOCK"; flock 9; }
echo "sear: $sear; default project, $DURATION s simulated per run, $RUNS runs each; $(nproc) cores; load $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-8s %10s %8s   %s\n' scenario "loop RTF" cost "[each run]"
declare -A rtf
# Interleaved, so that a change in the machine's load touches every scenario alike.
for ((i = 0; i < RUNS; ++i)); do
  for s in plain idle built watched replay; do
    rtf[$s]+="$(one_run "$s" "$work/$s.$i") "
  done
done
plain=$(printf '%s\n' ${rtf[plain]} | median)
for s in plain idle built watched replay; do
  m=$(printf '%s\n' ${rtf[$s]} | median)
  printf '%-8s %10.1f %7.1f%%   [%s]\n' "$s" "$m" "$(echo "100 * (1 - $m / $plain)" | bc -l)" "${rtf[$s]% }"
done
echo "frames read by the page in the last watched run: $(cat "$work/frames")"
