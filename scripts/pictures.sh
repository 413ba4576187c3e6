#!/usr/bin/env bash
# The README's pictures, from the bundled sample (samples/contact, an isg-synth scene):
#   scripts/pictures.sh            (after a build in build/, or ISG_BUILD_DIR)
# docs/images/before.png   the renderer's beauty (hard shadows, sharp reflections)
# docs/images/after.png    isg's composite (default preset)
# docs/images/reference.png the distribution-ray-traced reference
# docs/images/error_before.png, error_after.png   |error| against the reference, same scale
set -euo pipefail
cd "$(dirname "$0")/.."
isg=${ISG_BUILD_DIR:-build}/cli/isg
s=samples/contact
out=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
"$isg" run --scene $s/scene.json $s/aovs.exr -o "$tmp/after.exr" --preview "$out/after.png"
"$isg" run --scene $s/scene.json $s/aovs.exr -o "$tmp/before.exr" --preview "$out/before.png" \
  --set shadows.method=hard --set reflections.method=none
"$isg" run --scene $s/scene.json $s/ref/beauty.exr -o "$tmp/ref.exr" --preview "$out/reference.png" \
  --set shadows.method=none --set reflections.method=none 2>/dev/null ||
  oiiotool $s/ref/beauty.exr --ch R,G,B --colorconvert linear sRGB -o "$out/reference.png"
"$isg" compare "$tmp/before.exr" $s/ref/beauty.exr --channels R G B --heatmap "$out/error_before.png" --heatmap-max 0.1
"$isg" compare "$tmp/after.exr" $s/ref/beauty.exr --channels R G B --heatmap "$out/error_after.png" --heatmap-max 0.1
ls -l "$out"
