#!/usr/bin/env bash
# clang-tidy (the root .clang-tidy) over the planner, the runner, the effect interface and every
# effect's planner and recorder, with the build's compile commands: scripts/tidy.sh [BUILD_DIR].
# scripts/tidy.sh --full [BUILD_DIR]: every .cpp file of lib/, cli/, python/ and tools/, with the
# two costly checks the suite leaves out (.clang-tidy says which) turned back on; not run by the
# suite (about 20 minutes on two cores).
# A finding fails (WarningsAsErrors). Two files at a time, as CI has two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
full=0
if [ "${1:-}" = --full ]; then full=1; shift; fi
build=${1:-build}
tidy=$(command -v clang-tidy || command -v clang-tidy-14 || true)
if [ -z "$tidy" ]; then echo "clang-tidy not installed (Debian package clang-tidy)" >&2; exit 2; fi
[ -f "$build/compile_commands.json" ] || { echo "$build/compile_commands.json: build first" >&2; exit 2; }
files=(lib/plan/*.cpp lib/run/*.cpp lib/effects/effect.cpp lib/effects/recorder.cpp
       lib/effects/params.cpp lib/effects/*/effect.cpp lib/effects/*/recorder.cpp)
extra=()
if [ "$full" = 1 ]; then
  mapfile -t files < <(git ls-files 'lib/*.cpp' 'cli/*.cpp' 'python/*.cpp' 'tools/*.cpp')
  extra=(--checks=performance-unnecessary-value-param,bugprone-reserved-identifier)
fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
rc=0
printf '%s\n' "${files[@]}" |
  xargs -P 2 -n 1 "$tidy" -p "$build" --quiet --extra-arg=-Wno-unknown-warning-option --extra-arg=-Wno-ignored-optimization-argument "${extra[@]}" >"$log" 2>&1 || rc=$?
grep -v '^[0-9]* warnings\? generated\.$' "$log" >&2 || true
if [ "$rc" -ne 0 ] || grep -q 'error:\|warning:' "$log"; then
  echo "clang-tidy: findings above (exit $rc)" >&2
  exit 1
fi
echo "clang-tidy: ${#files[@]} files clean"
