#!/usr/bin/env python3
"""Numerical stability (issue 9): every method's error on hard inputs, in one table. The base is
isg-synth `contact` with a stress lens, f/0.25, so depth of field blurs 3-7 px (a ray-traced
reference for each effect); each row changes one thing:

- far world: the scene translated by (1e5, 1e5, 1e5) (isg-synth far-world), and by 1e6
  (isg-synth far-world-1e6), where P's float32 step (7.8 mm, 62.5 mm) is wider than a 16th of a
  pixel and P is refitted (input.positions);
- huge depth range: a backdrop 1e6 m behind the set, depth 1.5 to 1e6 m in one frame, the light's
  map seeing it beyond its far plane (isg-synth depth-range);
- grazing: the camera 0.55 m above the floor, 75-89° to its normal (isg-synth grazing);
- 4096² shadow map: the SAT methods' largest tables (shadow methods only);
- half floats: every channel of the AOVs and the shadow map stored as half (oiiotool -d half);
- NaN/Inf: 3x3 blocks of NaN, +Inf and -Inf in every channel of the AOVs (0.75% of pixels) and of
  the shadow map (0.2% of texels); errors are over the mask less the poisoned pixels.

Error: RMSE over the reference's mask of the effect's channel (key.softshadow against
ref/softshadow_key.exr, refl.glossy against ref/glossy.exr, the lens image against ref/dof.exr;
dof runs use hard shadows and no reflections so they compare with it). hard / none: the input.

    python3 bench/stability.py [--build build] [--size 480x270] [--spp 256] [--from-json]

Writes bench/out/stability.json and docs/benchmark/stability.md."""
import argparse, math, os, shutil, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import PAGES, Tools, compare, load, run_isg, save, sh, synth_case

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--cases", help="(unused: the rows are isg-synth scenes)")
ap.add_argument("--size", default="480x270")
ap.add_argument("--spp", type=int, default=256)
ap.add_argument("--from-json", action="store_true")
a = ap.parse_args()
t = Tools(a.build)

METHODS = {  # effect -> [(method, --set list)]
    "shadows": [(m, [f"shadows.method={m}", "reflections.method=none"]) for m in ("hard", "isg", "pcss", "cssm", "vssm")],
    "reflections": [("none", ["reflections.method=none"]), ("isg", ["reflections.method=isg"]),
                    ("blur", ["reflections.method=blur"])],
    "dof": [(m, [f"dof.method={m}", "shadows.method=hard", "reflections.method=none"]) for m in ("none", "isg", "layered")],
}
REFS = {"shadows": ("softshadow_key.exr", ["key.softshadow"], ["key.shadow"]),
        "reflections": ("glossy.exr", ["refl.glossy.R", "refl.glossy.G", "refl.glossy.B"], ["refl.R", "refl.G", "refl.B"]),
        "dof": ("dof.exr", ["R", "G", "B"], ["R", "G", "B"])}


def channels(path):
    return sh(["oiiotool", "--info", "-v", path]).split("channel list:")[1].split("\n")[0].count(",") + 1


def poison(src, dst, step, keep=None):
    """`src` with 3x3 blocks of NaN / +Inf / -Inf every `step` pixels in every channel; `keep`
    (if given) gets a one-channel image, 0 on the blocks and 1 elsewhere."""
    w, h = (int(v) for v in sh(["oiiotool", src, "--echo", "{TOP.width}x{TOP.height}"]).split()[0].split("x"))
    n = channels(src)
    cmd, kcmd = ["oiiotool", src], ["oiiotool", "--pattern", "constant:color=1", f"{w}x{h}", "1"]
    k = 0
    for y in range(step // 2, h - 3, step):
        for x in range(step // 3, w - 3, step):
            v = ("nan", "inf", "-inf")[k % 3]
            k += 1
            cmd += [f"--fill:color={','.join([v] * n)}", f"3x3+{x}+{y}"]
            kcmd += ["--fill:color=0", f"3x3+{x}+{y}"]
    sh(cmd + ["-o", dst])
    if keep:
        sh(kcmd + ["--chnames", "keep", "-d", "float", "-o", keep])


def derived(base, name, aovs_fn, map_fn):
    """A copy of case `base` (scene.json, ref/ shared) with its AOVs and map rewritten."""
    d = os.path.join(t.tmp, name)
    os.makedirs(d, exist_ok=True)
    shutil.copy(f"{base}/scene.json", d)
    if not os.path.exists(f"{d}/ref"):
        os.symlink(os.path.abspath(f"{base}/ref"), f"{d}/ref")
    aovs_fn(f"{base}/aovs.exr", f"{d}/aovs.exr")
    map_fn(f"{base}/shadowmap_key.exr", f"{d}/shadowmap_key.exr")
    return d


LENS = ["--fstop", "0.25"]  # a stress lens (16 cm aperture): out-of-focus blur of 3-7 px at 480x270


def case(scene, extra=(), name=None):
    return synth_case(t, scene, a.size, a.spp, [*LENS, *extra], name or f"{scene}-f0.25")


def measure():
    base = case("contact")
    half = lambda s, d: sh(["oiiotool", s, "-d", "half", "-o", d])
    keep = os.path.join(t.tmp, "keep.exr")
    rows = [
        ("baseline: isg-synth contact", base, None),
        ("far world (1e5 from the origin: P refitted)", case("far-world"), None),
        ("far world (1e6 from the origin: P refitted)", case("far-world-1e6"), None),
        ("huge depth range (backdrop at 1e6 m)", case("depth-range"), None),
        ("grazing (floor at 75-89° to the view)", case("grazing"), None),
        ("shadow map 4096²", case("contact", ["--shadowmap-size", "4096"], "contact-4096"), None),
        ("half-float AOVs and shadow map", derived(base, "half", half, half), None),
        ("NaN/Inf blocks in AOVs and shadow map", derived(base, "poison", lambda s, d: poison(s, d, 40, keep),
                                                        lambda s, d: poison(s, d, 64)), keep),
    ]
    out = {"size": a.size, "spp": a.spp, "rows": []}
    for label, d, keep_file in rows:
        row = {"condition": label, "errors": {}}
        for effect, methods in METHODS.items():
            if "4096" in label and effect != "shadows":
                continue
            ref, want, have = REFS[effect]
            mask = f"{d}/ref/{ref}:mask"
            if keep_file:  # the reference's mask less the poisoned pixels
                m = os.path.join(t.tmp, f"mask-{effect}.exr")
                sh(["oiiotool", f"{d}/ref/{ref}", "--ch", "mask", keep_file, "--mul", "--chnames", "mask", "-o", m])
                mask = f"{m}:mask"
            for method, sets in methods:
                try:
                    r = run_isg(t, d, sets)
                except subprocess.CalledProcessError as e:  # a failed run is a result too
                    row["errors"][f"{effect}.{method}"] = {"failed": (e.stderr or "").strip().splitlines()[-1:]}
                    continue
                o = r["out"]
                if method in ("hard", "none") and effect != "dof":
                    o = os.path.join(t.tmp, "input.exr")
                    sh(["oiiotool", r["out"], "--ch", ",".join(f"{w}={h}" for w, h in zip(want, have)), "-o", o])
                e = compare(t, o, f"{d}/ref/{ref}", want, mask)
                row["errors"][f"{effect}.{method}"] = e
                print(label, effect, method, f"{e['rmse']:.5f}", flush=True)
        out["rows"].append(row)
    save("stability.json", out)


def report():
    res = load("stability.json")
    cols = [f"{e}.{m}" for e, ms in METHODS.items() for m, _ in ms]
    L = ["# Numerical stability", "",
         "Generated by `python3 bench/stability.py` (run by `python3 bench/bench.py`). Every method "
         f"on isg-synth `contact` ({res['size']}, references at {res['spp']} spp, f/0.25 so that "
         "depth of field blurs 3-7 px) with one hard "
         "thing changed per row; RMSE of the effect's own channel over the reference's mask "
         "(NaN/Inf row: less the poisoned pixels). `hard` / `none` = the input, i.e. doing "
         "nothing. A failed run or a non-finite error would show as such.", "",
         "| condition | " + " | ".join(c.replace(".", " ") for c in cols) + " |",
         "|---|" + "---|" * len(cols)]
    for r in res["rows"]:
        cells = []
        for c in cols:
            e = r["errors"].get(c)
            if e is None:
                cells.append("-")
            elif "failed" in e:
                cells.append("failed")
            else:
                cells.append(f"{e['rmse']:.4f}" if math.isfinite(e["rmse"]) else "non-finite")
        L.append(f"| {r['condition']} | " + " | ".join(cells) + " |")
    fails = [(r["condition"], c, r["errors"][c]["failed"]) for r in res["rows"] for c in cols
             if "failed" in r["errors"].get(c, {})]
    if fails:
        L += ["", "Failed runs (isg's one-line error):", ""] + [f"- {cond}, {c}: `{' '.join(msg)}`" for cond, c, msg in fails]
    L += ["", "Errors are comparable down a column: the scenes share geometry (grazing and depth range see "
          "it from elsewhere or add a backdrop, so their doing-nothing errors differ too).", ""]
    os.makedirs(PAGES, exist_ok=True)
    open(os.path.join(PAGES, "stability.md"), "w").write("\n".join(L))
    print("wrote docs/benchmark/stability.md")


if not a.from_json:
    measure()
report()
