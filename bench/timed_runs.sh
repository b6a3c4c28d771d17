# The one timing loop of the bench scripts that time `sear run` (run_rtf.sh, arduino_rtf.sh,
# avr_engine_rtf.sh, side_by_side.sh); sourced, not run. A run's loop real-time factor is its
# summary.json's real_time_factor (simulated seconds per wall second from the first step to the
# last); its whole time is what `time sear run` sees, start to exit, start-up and firmware from the
# cache included. A run's plots are drawn in the background after it exits: the time until they
# are all in place is measured apart (the plotter holds an flock on the output folder), and waited
# for before the next run starts, so that no run shares the cores with an earlier run's plotter.

# bench_sear NAME [PATH]: the sear binary to time: PATH, else $ROOT's build-release, else its build.
bench_sear() {
  local name=$1 sear=${2:-}
  if [[ -z $sear ]]; then
    for candidate in "$ROOT/build-release/tools/sear" "$ROOT/build/tools/sear"; do
      [[ -x $candidate ]] && { sear=$candidate; break; }
    done
  fi
  [[ -x ${sear:-} ]] || { echo "$name: no sear binary (give its path)" >&2; exit 2; }
  echo "$sear"
}

# bench_median: the median of the numbers on standard input, one a line.
bench_median() {
  sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

# bench_column N: the Nth field of each line on standard input.
bench_column() { awk -v n="$1" '{ print $n }'; }

# bench_absolute_paths: a project of $ROOT/assets/projects on standard input with its relative
# paths made absolute, so that it runs from anywhere, on standard output.
bench_absolute_paths() {
  sed -e "s#\\([\" ]\\)\\.\\./\\.\\./#\\1$ROOT/#g" -e "s#\\([\" ]\\)\\.\\./#\\1$ROOT/assets/#g"
}

# bench_nolidar_project: the default project (the reference rover) without its LMS200, its paths
# made absolute, on standard output.
bench_nolidar_project() { grep -v "<lms2xx" "$ROOT/assets/projects/default.xml" | bench_absolute_paths; }

# bench_forest_project: the reference rover's project in its world crowded with 400 more
# obstacles over the arena (crates, trees and, a third of them, loose boxes that ODE solves as they
# settle on the hills), its paths absolute from $ROOT, on standard output. The same world on every machine: the
# places come from Park and Miller's minimal standard generator, exact in awk's doubles.
bench_forest_project() {
  awk '
    function next_unit() { seed = (seed * 16807) % 2147483647; return seed / 2147483647 }
    BEGIN { seed = 3 }
    /<\/world>/ {
      for (n = 0; n < 400;) {
        x = -14 + 28 * next_unit(); y = -14 + 26 * next_unit()
        if (x * x + y * y < 9) continue  # the start stays clear
        if (n % 3 == 0) printf "    <box name=\"crate%d\" pos=\"%.2f %.2f\" size=\"0.2 0.2 0.3\" material=\"wood\"/>\n", n, x, y
        else if (n % 3 == 1) printf "    <tree name=\"tree%d\" pos=\"%.2f %.2f\" trunk_radius=\"0.1\" trunk_height=\"2\" crown_radius=\"0.6\" material=\"wood\"/>\n", n, x, y
        else printf "    <box name=\"loose%d\" pos=\"%.2f %.2f\" size=\"0.3 0.3 0.3\" mass=\"0.5\" material=\"wood\"/>\n", n, x, y
        n++
      }
    }
    { print }' "$ROOT/assets/projects/default.xml" | bench_absolute_paths
}

# bench_load: the load average over 1, 5 and 15 minutes, now.
bench_load() { cut -d' ' -f1-3 /proc/loadavg; }

# bench_warm SEAR OUT PROJECT [ARGS...]: one untimed run of 0.1 s, which compiles the firmware into
# the cache and warms the page cache.
bench_warm() {
  local sear=$1 out=$2
  shift 2
  "$sear" run "$@" --duration 0.1 --quiet -o "$out" >/dev/null 2>&1 || true
  flock "$out" true 2>/dev/null || true
}

# bench_runs SEAR RUNS DURATION OUT PROJECT [ARGS...]: RUNS timed runs of DURATION simulated
# seconds into OUT.1, OUT.2..., each printing one line: loop real-time factor, whole-run wall
# seconds, simulated seconds, seconds its plots took after the exit (about 0 without plots, or
# with a sear that draws them before it exits), and the microseconds a step spent before the
# quantum, in the capture, in physics and after the quantum (summary.json's step_wall_us; "-"
# from a sear that does not write it). Warm up first (bench_warm). The elements of the
# array BENCH_PREFIX, if set, go before sear (taskset -c 0, unshare ...). A failed run ends the script.
bench_runs() {
  local sear=$1 runs=$2 duration=$3 out=$4
  shift 4
  local i t0 t1 t2
  for ((i = 1; i <= runs; ++i)); do
    t0=$(date +%s.%N)
    "${BENCH_PREFIX[@]}" "$sear" run "$@" --duration "$duration" --quiet -o "$out.$i" >/dev/null 2>"$out.$i.err" ||
      { echo "bench: $sear run $* failed:" >&2; cat "$out.$i.err" >&2; exit 1; }
    t1=$(date +%s.%N)
    flock "$out.$i" true
    t2=$(date +%s.%N)
    jq -r --arg whole "$(echo "$t1 - $t0" | bc -l)" --arg plots "$(echo "$t2 - $t1" | bc -l)" \
      '"\(.real_time_factor) \($whole | tonumber) \(.sim_time_s) \($plots | tonumber) " +
       ([.step_wall_us | (.before_quantum, .capture, .physics, .after_quantum) // "-"] | map(tostring) | join(" "))' \
      "$out.$i/summary.json"
  done
}
