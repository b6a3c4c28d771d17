#!/usr/bin/env bash
# Rewrites the reference of the device elements in docs/project.md (the lines between
# `<!-- sear sensors --markdown -->` and the next `<!-- end -->`) from `sear sensors --markdown`, which
# reads the loader's own table; tests/sensors_command_test.cpp fails while the two differ.
# --check only reports whether the page is up to date (exit 1 if not), for CI.
# SEAR=path/to/sear uses that binary; otherwise build/tools/sear is built first.
set -euo pipefail
cd "$(dirname "$0")/.."
page=docs/project.md

check=false
case "${1:-}" in
  --check) check=true ;;
  "") ;;
  *) echo "usage: $0 [--check]" >&2; exit 2 ;;
esac

sear=${SEAR:-}
if [ -z "$sear" ]; then
  cmake -S . -B build >/dev/null
  cmake --build build -j"$(nproc)" --target sear >/dev/null
  sear=build/tools/sear
fi

reference=$(mktemp)
updated=$(mktemp)
trap 'rm -f "$reference" "$updated"' EXIT
"$sear" sensors --markdown >"$reference"

# Copies the page, putting the reference in place of whatever stood between the markers.
awk -v reference="$reference" -v page="$page" '
  skipping && $0 == "<!-- end -->" { skipping = 0; ended = 1 }
  skipping { next }
  { print }
  $0 == "<!-- sear sensors --markdown -->" && !started {
    started = 1; skipping = 1
    while ((getline line < reference) > 0) print line
  }
  END {
    if (!started) { print page " has no line <!-- sear sensors --markdown -->" > "/dev/stderr"; exit 1 }
    if (!ended) { print page " has no <!-- end --> after <!-- sear sensors --markdown -->" > "/dev/stderr"; exit 1 }
  }
' "$page" >"$updated"

if cmp -s "$page" "$updated"; then
  echo "$page's device reference is up to date."
elif $check; then
  echo "$page's device reference differs from \`sear sensors --markdown\`; run $0" >&2
  diff -u "$page" "$updated" >&2 || true
  exit 1
else
  # Written over in place, so the page keeps its mode and its inode.
  cat "$updated" >"$page"
  echo "$page's device reference rewritten from \`sear sensors --markdown\`."
fi
