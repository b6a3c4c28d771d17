#!/usr/bin/env bash
# README's second command, and what CI runs: installs what is missing, builds everything, runs the
# GoogleTest suites through ctest, then the fuzzers (project files, LMS2xx telegrams, GPS commands)
# for a short while each.
# SEAR_SANITIZE=address,undefined runs the suites under the sanitizers instead (in build-sanitize/).
# SEAR_FUZZ_SECONDS sets how long each fuzzer runs (default 20; 0 skips them).
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
# A one-node Slurm for the sharding test's array job, stopped again when this script ends.
if [ "$(id -u)" -eq 0 ] && slurm_env=$(scripts/slurm-local.sh start "$build/slurm"); then
  eval "$slurm_env"
  trap 'scripts/slurm-local.sh stop "$build/slurm"' EXIT
fi
ctest --test-dir "$build" --output-on-failure -j"$jobs"

fuzz_seconds=${SEAR_FUZZ_SECONDS:-20}
# Runs one libFuzzer target on a copy of its seeds for fuzz_seconds; stops the script on a finding.
fuzz() {
  local target=$1 seeds=$2 dict=$3
  local corpus
  corpus=$(mktemp -d)
  cp $seeds "$corpus"/
  echo "Fuzzing ${target} for ${fuzz_seconds} s"
  # libFuzzer exits non-zero on a crash, leak, timeout or sanitizer report and saves the input.
  local status=0
  build-fuzz/tests/fuzz/"$target" -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=4096 \
    ${dict:+-dict="$dict"} -artifact_prefix=build-fuzz/artifacts/ -print_final_stats=1 \
    "$corpus" >build-fuzz/"$target".log 2>&1 || status=$?
  rm -rf "$corpus"
  if [ "$status" -ne 0 ]; then
    tail -n 60 build-fuzz/"$target".log >&2
    echo "The fuzzer found a failing input for ${target} (exit $status), saved in build-fuzz/artifacts/" >&2
    exit 1
  fi
  grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added)" build-fuzz/"$target".log
}

if [ "$fuzz_seconds" -gt 0 ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -DSEAR_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build build-fuzz -j"$jobs" --target project_loader_fuzz lms2xx_fuzz gnss_command_fuzz
  mkdir -p build-fuzz/artifacts
  fuzz project_loader_fuzz "assets/projects/*.xml assets/robots/*.xml" tests/fuzz/project.dict
  fuzz lms2xx_fuzz "tests/fuzz/lms2xx_corpus/*" ""
  fuzz gnss_command_fuzz "tests/fuzz/gnss_corpus/*" tests/fuzz/gnss.dict
  echo "Fuzzing found nothing."
fi
