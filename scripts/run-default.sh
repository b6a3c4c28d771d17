#!/usr/bin/env bash
# README's first command: installs what is missing, builds `sear`, and runs the bundled default
# project headless (extra arguments go to `sear run`, e.g. --duration 60 --out my-run).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target sear >/dev/null
exec build/tools/sear run "$@"
