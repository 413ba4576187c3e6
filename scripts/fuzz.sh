#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz, clang + ASan/UBSan) and runs each for a set time.
#   scripts/fuzz.sh [SECONDS] [exr|scene|preset ...]      default: 60 s each, all three
#   scripts/fuzz.sh 0                                       build only
# The corpus grows in $ISG_FUZZ_BUILD_DIR/corpus/<harness>, seeded from tests/fuzz/seeds; a crash,
# hang (-timeout) or leak leaves its input there and exits non-zero.
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
[ $# -gt 0 ] && shift
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=(exr scene preset)
fz=${ISG_FUZZ_BUILD_DIR:-build-fuzz}
main=$(realpath -m "${ISG_BUILD_DIR:-build}")

if [ "${ISG_FUZZ_SKIP_BUILD:-0}" != 1 ]; then
  cmake -S tests/fuzz -B "$fz" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$fz"
fi
[ "$secs" = 0 ] && exit 0
# The EXR harness decodes through isg-exrcheck, as isg does.
[ -x "$main/cli/isg-exrcheck" ] && export ISG_EXRCHECK="$main/cli/isg-exrcheck"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
for h in "${harnesses[@]}"; do
  corpus="$fz/corpus/$h"
  mkdir -p "$corpus" "$fz/artifacts/$h"
  cp -n tests/fuzz/seeds/$h/* "$corpus/" 2>/dev/null || true
  # The EXR harness also starts from the crafted damaged headers of every compression (issue 54:
  # tests/support/exr_craft.py), written here rather than kept in the repository.
  [ "$h" = exr ] && python3 tests/support/exr_craft.py "$corpus"
  echo "== fuzz_$h for ${secs}s"
  log="$fz/fuzz_$h.log"
  rc=0
  "$fz/fuzz_$h" "$corpus" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$fz/artifacts/$h/" >"$log" 2>&1 || rc=$?
  grep -E "^(stat::|==[0-9]+==ERROR|SUMMARY|Done)|INFO: seed corpus|DONE|INITED" "$log" || true
  if [ "$rc" -ne 0 ]; then
    echo "fuzz_$h FAILED (exit $rc): input in $fz/artifacts/$h, log $log"
    exit 1
  fi
done
