#!/usr/bin/env bash
# README's second command, and what CI runs: installs what is missing, builds everything, runs the
# GoogleTest suites through ctest, then the project-file fuzzer for a short while.
# SEAR_SANITIZE=address,undefined runs the suites under the sanitizers instead (in build-sanitize/).
# SEAR_FUZZ_SECONDS sets how long the fuzzer runs (default 30; 0 skips it).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
jobs=$(nproc)

build=build
extra=()
if [ -n "${SEAR_SANITIZE:-}" ]; then
  build=build-sanitize
  extra=(-DSEAR_SANITIZE="$SEAR_SANITIZE" -DCMAKE_BUILD_TYPE=Debug)
fi
cmake -S . -B "$build" "${extra[@]}" >/dev/null
cmake --build "$build" -j"$jobs"
ctest --test-dir "$build" --output-on-failure -j"$jobs"

fuzz_seconds=${SEAR_FUZZ_SECONDS:-30}
if [ "$fuzz_seconds" -gt 0 ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -DSEAR_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build build-fuzz -j"$jobs" --target project_loader_fuzz
  corpus=$(mktemp -d)
  cp assets/projects/*.xml assets/robots/*.xml "$corpus"/
  mkdir -p build-fuzz/artifacts
  echo "Fuzzing the project loader for ${fuzz_seconds} s"
  # libFuzzer exits non-zero on a crash, leak, timeout or sanitizer report and saves the input.
  status=0
  build-fuzz/tests/fuzz/project_loader_fuzz -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=4096 \
    -dict=tests/fuzz/project.dict -artifact_prefix=build-fuzz/artifacts/ -print_final_stats=1 \
    "$corpus" >build-fuzz/fuzz.log 2>&1 || status=$?
  rm -rf "$corpus"
  if [ "$status" -ne 0 ]; then
    tail -n 60 build-fuzz/fuzz.log >&2
    echo "The fuzzer found a failing input (exit $status), saved in build-fuzz/artifacts/" >&2
    exit 1
  fi
  grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added)" build-fuzz/fuzz.log
  echo "Fuzzing found nothing."
fi
