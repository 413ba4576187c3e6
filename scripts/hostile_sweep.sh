#!/usr/bin/env bash
# Runs `isg info` and `isg run` on every file in the given folders (e.g. a fuzz corpus) and
# reports exit codes, crashes, hangs and the peak resident memory reached.
#   scripts/hostile_sweep.sh DIR... (uses ${ISG_BUILD_DIR:-build}/cli/isg)
set -u
isg=$(realpath "${ISG_BUILD_DIR:-build}/cli/isg")
out=$(mktemp -d)
n=0; ok=0; err=0; bad=0; peak_info=0; peak_run=0
for f in $(find "$@" -type f); do
  n=$((n + 1))
  for cmd in info run; do
    args=("$cmd" "$f"); [ "$cmd" = run ] && args+=(-o "$out/o.exr")
    /usr/bin/time -o "$out/t" -f "%M" timeout 60 "$isg" "${args[@]}" >/dev/null 2>"$out/err"
    rc=$?
    m=$(tail -n 1 "$out/t")
    [ "$cmd" = info ] && [ "${m:-0}" -gt "$peak_info" ] && peak_info=$m
    [ "$cmd" = run ] && [ "${m:-0}" -gt "$peak_run" ] && peak_run=$m
    lines=$(grep -c . "$out/err" || true)
    case "$rc" in
      0) ok=$((ok + 1)) ;;
      1) err=$((err + 1)); [ "$lines" -gt 2 ] && echo "multi-line error: $cmd $f" ;;
      *) bad=$((bad + 1)); echo "CRASH/HANG (exit $rc): isg $cmd $f" ;;
    esac
    rm -f "$out/o.exr"
  done
done
echo "files: $n; runs: ok $ok, one-line errors $err, crashes/hangs $bad"
echo "peak RSS: isg info ${peak_info} KiB, isg run ${peak_run} KiB"
rm -rf "$out"
