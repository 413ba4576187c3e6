#!/bin/bash
# On a GPU machine, from the repository root, with the tarball of scripts/device/bundle.py:
#   bash scripts/device/check.sh PACK.tar.xz [OUTDIR]
# Issue 18's GPU figures and every GPU test with the validation layer on: per-pass timings
# (--timings, three runs; the last printed) for the default preset and each method, bench/speed.py
# against oiiotool, a 12-frame 1080p sequence against oiiotool one process a frame.
R=$PWD; G=/tmp/isg-device; O=${2:-/tmp/isg-device-out}
mkdir -p $G $O && tar xJf "$1" -C $G || exit 1
export LD_LIBRARY_PATH=$G/lib VK_LAYER_PATH=$G/layer XDG_RUNTIME_DIR=/tmp ISG_PRESET_PATH=$R/presets
export PATH=$G/bin:$G/B/cli:$G/B/tools/synth:$PATH PYTHONUNBUFFERED=1
ICD=$(ls /usr/share/vulkan/icd.d/nvidia_icd*.json /etc/vulkan/icd.d/nvidia_icd*.json 2>/dev/null | head -1)
[ -n "$ICD" ] && export VK_DRIVER_FILES=$ICD
isg devices || exit 2
S=/tmp/isg-device-case; mkdir -p $S
isg-synth contact --out $S/c --width 1920 --height 1080 --no-refs > /dev/null || exit 1
for m in "" "--set dof.method=layered" "--set dof.method=isg" "--set shadows.method=pcss" \
         "--set shadows.method=vssm" "--set shadows.method=cssm" "--set shadows.method=auto"; do
  for k in 1 2 3; do isg run $S/c/aovs.exr --scene $S/c/scene.json -o $S/o.exr $m --timings > $S/t.txt 2>&1; done
  echo "## isg run (1080p contact) $m"; cat $S/t.txt
done
python3 bench/speed.py --build $G/B --repeat 3 | tail -5; cp bench/out/speed.json docs/benchmark/speed.md $O/
mkdir -p $S/seq; for i in $(seq -w 1 12); do cp $S/c/aovs.exr $S/seq/in.00$i.exr; done
t0=$EPOCHREALTIME; isg run $S/seq/in.####.exr --frames 1-12 --scene $S/c/scene.json -o $S/seq/out.####.exr > /dev/null
echo "isg, 12 frames in one process: $(awk "BEGIN{print $EPOCHREALTIME - $t0}") s (rc $?)"
t0=$EPOCHREALTIME; for i in $(seq -w 1 12); do oiiotool $S/seq/in.00$i.exr -o $S/seq/copy.00$i.exr; done
echo "oiiotool, 12 frames one process each: $(awk "BEGIN{print $EPOCHREALTIME - $t0}") s"
for t in $G/bin/isg_*_tests; do
  (timeout 300 $t --gtest_brief=1 > $O/$(basename $t).log 2>&1
   echo "$(basename $t) rc=$? $(grep -E 'PASSED|FAILED' $O/$(basename $t).log | tr '\n' ' ')") &
done
wait
