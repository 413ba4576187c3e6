#!/usr/bin/python3
"""A finished case moved far from the origin after rendering: what a renderer with exact arithmetic
would write for the same scene translated by OFFSET, with P stored as float32.

usage: translate_case.py SRC DST OFFSET [OFFSET OFFSET]     (one value: the same on x, y and z)

P (aovs.exr's P.X/P.Y/P.Z and cycles_native.exr's Position, which Blender accumulates times
alpha) becomes float32(float64(P) + OFFSET) on foreground pixels; scene.json's world_to_camera and
world_to_light get the translation folded in, in float64, and the light's position moves.
Everything else is the same under a translation and is copied as it is: Z, N, key.shadow,
key.occluder, key.direct, the shadow map (planar depth from the light), the references. So the
moved case differs from SRC only in the precision of P: a method's error on the two should be the
same (issue 19). Unlike a Cycles render made far from the origin (make_cases.sh contact-far1e5),
the geometry is not re-tessellated in float32 and the references do not change.
Needs python3-openimageio and python3-numpy (system python). DST is replaced only on success.
"""
import json
import os
import shutil
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio


def fail(msg):
    print(f"translate_case.py: {msg}", file=sys.stderr)
    sys.exit(1)


def move_positions(path, names, alpha, depth, offset):
    """Adds offset (times alpha where `alpha` is given) to the channels `names` on foreground pixels."""
    inp = oiio.ImageInput.open(path)
    if inp is None:
        fail(f"{path}: {oiio.geterror()}")
    spec = oiio.ImageSpec(inp.spec())
    if inp.seek_subimage(1, 0):
        fail(f"{path}: several parts (one expected)")
    px = np.asarray(inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT), np.float64)
    inp.close()
    chans = list(spec.channelnames)
    missing = [n for n in names + [depth] + ([alpha] if alpha else []) if n not in chans]
    if missing:
        fail(f"{path}: no channel {missing[0]}")
    z = px[..., chans.index(depth)]
    a = px[..., chans.index(alpha)] if alpha else np.ones_like(z)
    fg = (z > 0) & (z < 1e9) & ((a > 1e-3) if alpha else True)
    for n, d in zip(names, offset):
        i = chans.index(n)
        px[..., i] = np.where(fg, (px[..., i] + d * a).astype(np.float32), px[..., i])
    tmp = path + ".tmp.exr"
    out = oiio.ImageOutput.create(tmp)    # the input's spec: channels, pixel type per channel, attributes
    if out is None or not out.open(tmp, spec) or not out.write_image(px.astype(np.float32)):
        fail(f"{path}: {oiio.geterror() if out is None else out.geterror()}")
    out.close()
    os.replace(tmp, path)
    return int(fg.sum())


def translate_matrix(rows, offset):
    """world_to_X of the moved scene: M · T(-offset), in float64."""
    m = np.array(rows, np.float64).reshape(4, 4)
    t = np.eye(4)
    t[:3, 3] = -np.asarray(offset)
    return [float(v) for v in (m @ t).reshape(-1)]


def main():
    if len(sys.argv) not in (4, 6):
        fail("usage: translate_case.py SRC DST OFFSET [OFFSET OFFSET]")
    src, dst = sys.argv[1], sys.argv[2].rstrip("/")
    try:
        offset = [float(v) for v in sys.argv[3:]] * (3 if len(sys.argv) == 4 else 1)
    except ValueError:
        fail(f"bad OFFSET {' '.join(sys.argv[3:])}")
    for f in ("aovs.exr", "scene.json", "README.md"):
        if not os.path.exists(f"{src}/{f}"):
            fail(f"{src}: no {f}")
    parent = os.path.dirname(os.path.abspath(dst))
    os.makedirs(parent, exist_ok=True)
    work = tempfile.mkdtemp(prefix=".translate-", dir=parent)
    try:
        stage = os.path.join(work, "case")
        shutil.copytree(src, stage, copy_function=shutil.copyfile)
        for root, dirs, _ in os.walk(stage):    # the source may be read-only (../shared)
            for d in [root] + [os.path.join(root, x) for x in dirs]:
                os.chmod(d, 0o755)
        n = move_positions(f"{stage}/aovs.exr", ["P.X", "P.Y", "P.Z"], None, "Z", offset)
        if os.path.exists(f"{stage}/cycles_native.exr"):
            vl = "ViewLayer"
            move_positions(f"{stage}/cycles_native.exr", [f"{vl}.Position.{c}" for c in "XYZ"],
                           f"{vl}.Combined.A", f"{vl}.Depth.Z", offset)
        S = json.load(open(f"{stage}/scene.json"))
        S["camera"]["world_to_camera"] = translate_matrix(S["camera"]["world_to_camera"], offset)
        for L in S["lights"]:
            L["position"] = [p + d for p, d in zip(L["position"], offset)]
            if "shadowmap" in L:
                L["shadowmap"]["world_to_light"] = translate_matrix(L["shadowmap"]["world_to_light"], offset)
        json.dump(S, open(f"{stage}/scene.json", "w"), indent=2)
        step = float(np.spacing(np.float32(max(abs(d) for d in offset))))
        readme = open(f"{stage}/README.md").read()
        name = os.path.basename(os.path.normpath(src))
        note = (f"# Case `{os.path.basename(dst)}`\n\n**Moved copy of `{name}`** by the isg repository's "
                f"`tools/cases/translate_case.py`: the same render translated by ({', '.join(f'{d:g}' for d in offset)}) "
                f"m after rendering. P (aovs.exr's P.X/P.Y/P.Z on {n} foreground pixels, and cycles_native.exr's "
                f"Position) is float32(float64(P) + offset), so its step is {step:g} m; scene.json's matrices and the "
                "light's position include the translation (float64); every other channel, the shadow map and the "
                "references are the original's, which a translation leaves unchanged. The original README follows; "
                "its positions are the original's.\n\n")
        open(f"{stage}/README.md", "w").write(note + readme)
        if os.path.exists(dst):
            shutil.rmtree(dst)
        os.replace(stage, dst)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"{dst}: {src} moved by {offset}, P step {step:g} m")


if __name__ == "__main__":
    main()
