#!/usr/bin/env bash
# Render one case of tools/cases/scenes.py (the shared scene table plus the repository's own scenes)
# with the shared Cycles generator, ../shared/tools/cases/make_cases.sh, unchanged.
#
# usage: tools/cases/make_cases.sh CASE OUTDIR [--quick] [--reuse]     (as the shared script)
#        tools/cases/make_cases.sh --list | --own     (every scene | the repository's own scenes)
# The shared driver runs the scripts next to itself; it is run here from a temporary folder holding
# a link to it and links to this folder's wrappers (render_case.py, post_case.py, write_readme.py),
# which load the shared scripts with this folder's scenes.py. ISG_CASES_SHARED_TOOLS overrides where
# the shared generator is (default: ../shared/tools/cases next to the repository).
# Blender runs under `nice -n ${ISG_CASES_NICE:-19}`.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd -P)
shared=${ISG_CASES_SHARED_TOOLS:-$here/../../../shared/tools/cases}
[ -f "$shared/make_cases.sh" ] || { echo "make_cases.sh: no shared generator at $shared (set ISG_CASES_SHARED_TOOLS)" >&2; exit 2; }
export ISG_CASES_SHARED_TOOLS=$(cd "$shared" && pwd -P)
if [ "${1:-}" = --list ] || [ "${1:-}" = --own ]; then
  /usr/bin/python3 -c "import sys; sys.path.insert(0, '$here'); import scenes; print('\n'.join(scenes.SCENES if sys.argv[1] == '--list' else scenes.OWN))" "$1"
  exit 0
fi
[ $# -ge 2 ] || { echo "usage: $0 CASE OUTDIR [--quick] [--reuse] | --list" >&2; exit 2; }
/usr/bin/python3 -c "import sys; sys.path.insert(0, '$here'); import scenes; sys.exit(0 if sys.argv[1] in scenes.SCENES else 1)" "$1" ||
  { echo "make_cases.sh: unknown case '$1' (see --list)" >&2; exit 2; }

command -v blender >/dev/null || { echo "make_cases.sh: no blender (apt-get install blender python3-openimageio python3-numpy)" >&2; exit 2; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/isg-cases-driver.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
ln -s "$ISG_CASES_SHARED_TOOLS/make_cases.sh" "$tmp/make_cases.sh"
for f in render_case.py post_case.py write_readme.py; do ln -s "$here/$f" "$tmp/$f"; done
# the shared driver calls `blender` from PATH: a shim that runs it niced
mkdir "$tmp/bin"
printf '#!/bin/sh\nexec nice -n %s %s "$@"\n' "${ISG_CASES_NICE:-19}" "$(command -v blender)" >"$tmp/bin/blender"
chmod +x "$tmp/bin/blender"
PATH="$tmp/bin:$PATH" "$tmp/make_cases.sh" "$@"
