#!/usr/bin/env bash
# README's first command: installs what is missing, builds `sear` in build/ of this clone, and runs
# the bundled default project headless from the caller's folder, where its outputs go (extra
# arguments go to `sear run`, e.g. --duration 60 --out my-run).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build"
"$root/scripts/install-deps.sh"
# The same configuration as scripts/test.sh (the project's default build type), so that running
# one after the other does not rebuild everything.
echo "sear: configuring $build" >&2
cmake -S "$root" -B "$build" >/dev/null
# cmake's own percentage, one line per step, so a first build that takes minutes is seen to move;
# the whole log is kept and shown if the build fails.
log="$build/run-default-build.log"
echo "sear: building sear (a first build compiles the simulator, ODE bindings and viewer: minutes; later ones seconds)" >&2
if ! cmake --build "$build" -j"$(nproc)" --target sear >"$log" 2>&1; then
  tail -n 60 "$log" >&2
  echo "sear: the build failed; the whole log is $log" >&2
  exit 1
fi &
build_pid=$!
shown=""
while kill -0 "$build_pid" 2>/dev/null; do
  percent=$(grep -E '^\[ *[0-9]+%\] (Building|Linking)' "$log" 2>/dev/null | tail -n 1 | cut -d']' -f1 |
    tr -d '[ ' || true)
  if [ -n "$percent" ] && [ "$percent" != "$shown" ]; then
    echo "sear: build $percent" >&2
    shown=$percent
  fi
  sleep 2
done
wait "$build_pid"
exec "$build/tools/sear" run "$@"
