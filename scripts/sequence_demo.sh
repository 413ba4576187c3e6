#!/usr/bin/env bash
# Issue 10's sequence demo: a 24-frame moving isg-synth sequence processed in one command,
# interrupted and resumed, one corrupted frame reported while the rest finish, and frames per
# second against the I/O floor (oiiotool copying the same frames).
#   scripts/sequence_demo.sh [DIR] [WIDTHxHEIGHT]      (default /tmp/isg-seq, 640x360)
set -euo pipefail
cd "$(dirname "$0")/.."
b=${ISG_BUILD_DIR:-build}
dir=${1:-/tmp/isg-seq}
size=${2:-640x360}
w=${size%x*}; h=${size#*x}
rm -rf "$dir"; mkdir -p "$dir/in" "$dir/out"
for f in $(seq 1 24); do
  "$b/tools/synth/isg-synth" contact --frame "$f" --out "$dir/gen" --width "$w" --height "$h" --no-refs >/dev/null
  cp "$dir/gen/aovs.exr" "$dir/in/shot.$(printf %04d "$f").exr"
done
scene="$dir/gen/scene.json"
run() { "$b/cli/isg" run "$dir/in/shot.####.exr" --scene "$scene" -o "$dir/out/shot.####.exr" --frames 1-24 "$@"; }

echo "== 1. whole range, timed"
t0=$(date +%s.%N); run; t1=$(date +%s.%N)
echo "== 2. I/O floor: oiiotool copies of the same frames"
t2=$(date +%s.%N)
for f in "$dir"/in/shot.*.exr; do oiiotool "$f" -o "$dir/copy.exr"; done
t3=$(date +%s.%N)
python3 -c "a=$t1-$t0; b=$t3-$t2; print(f'isg: {a:.2f} s, {24/a:.2f} frames/s; oiiotool: {b:.2f} s, {24/b:.2f} frames/s; ratio {a/b:.2f}')"
echo "== 3. interrupted after 12 s, then resumed with --skip-existing"
rm -f "$dir"/out/*
timeout -s INT 12 bash -c "$(declare -f run); b=$b dir=$dir scene=$scene; run" || echo "(interrupted: $(ls "$dir/out" | wc -l) frames written)"
run --skip-existing
echo "== 4. frame 12 truncated: reported, the other 23 finish (--keep-going)"
rm -f "$dir"/out/*
head -c 2000 "$dir/in/shot.0012.exr" > "$dir/t" && mv "$dir/t" "$dir/in/shot.0012.exr"
set +e; run --keep-going; rc=$?; set -e
echo "exit status $rc; $(ls "$dir/out" | wc -l) frames written"
