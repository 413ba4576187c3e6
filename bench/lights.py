#!/usr/bin/env python3
"""Issue 52's tables: the lights film shots are lit by. isg-synth `sun` (a low sun over contact's
geometry, orthographic map), `spot` and `three-lights` (key sphere, sun, rect fill): for every
shadow method, each light's L.softshadow against its distribution-ray-traced reference over the
reference's mask, next to doing nothing (the input's L.shadow against the same reference), and the
composite against ref/beauty.exr next to the input's beauty. Then the speed of several lights:
three-lights against contact (the same frame and camera, the key alone) at --speed-size, GPU time
per light from the timestamp queries and wall time, best of --repeat.

    python3 bench/lights.py [--build build] [--size 480x270] [--spp 256] [--speed-size 1920x1080]

Writes bench/out/lights.json and docs/benchmark/lights.md."""
import argparse, os, platform, re, sys, time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
from common import PAGES, Tools, compare, run_isg, save, synth_case

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--size", default="480x270")
ap.add_argument("--spp", type=int, default=256)
ap.add_argument("--speed-size", default="1920x1080")
ap.add_argument("--repeat", type=int, default=3)
a = ap.parse_args()
T = Tools(a.build)

# (label, scene, its lights, isg-synth options): the sun's map covers the whole 20 m scene, at
# 1024² (a texel 2 cm, 1.5 pixels at the receivers) and at 4096².
SCENES = [("sun", "sun", ["sun"], []),
          ("sun, 4096² map", "sun", ["sun"], ["--shadowmap-size", "4096"]),
          ("spot", "spot", ["spot"], []),
          ("three-lights", "three-lights", ["key", "sun", "fill"], [])]
METHODS = ["isg", "pcss", "vssm", "cssm", "auto"]


def light_error(out, case, light):
    ref = f"{case}/ref/softshadow_{light}.exr"
    return compare(T, out, ref, [f"{light}.softshadow"], f"{ref}:mask")["rmse"]


def composite_error(out, case):
    ref = f"{case}/ref/beauty.exr"
    return compare(T, out, ref, ["R", "G", "B"], f"{ref}:mask")["rmse"]


rows = []
for label, scene, lights, extra in SCENES:
    case = synth_case(T, scene, a.size, a.spp, extra, name=f"{scene}-{a.size}-{len(extra)}")
    nothing = composite_error(f"{case}/aovs.exr", case)
    # Doing nothing: method hard writes the input's L.shadow as L.softshadow.
    hard = run_isg(T, case, ["shadows.method=hard"], out=os.path.join(T.tmp, "hard.exr"))
    hard_err = {l: light_error(hard["out"], case, l) for l in lights}
    for m in METHODS:
        r = run_isg(T, case, [f"shadows.method={m}"])
        row = {"scene": label, "method": m, "composite": composite_error(r["out"], case),
               "composite_nothing": nothing, "lights": {}}
        for l in lights:
            row["lights"][l] = {"rmse": light_error(r["out"], case, l), "nothing": hard_err[l]}
        rows.append(row)
        print(label, m, {l: round(v["rmse"] / v["nothing"], 3) for l, v in row["lights"].items()},
              "composite", round(row["composite"] / nothing, 3), flush=True)

# Own Cycles cases (tools/cases, rendered into $ISG_OWN_CASES, default ../cases-own; skipped
# where absent): their light by name, each method against ref/softshadow_<light>.exr.
own_dir = os.environ.get("ISG_OWN_CASES", os.path.join(here, "..", "..", "cases-own"))
cycles = []
for case, light in (("sun", "sun"),):
    d = os.path.join(own_dir, case)
    if not os.path.isfile(os.path.join(d, "ref", f"softshadow_{light}.exr")):
        print("own Cycles case", case, "absent: skipped", flush=True)
        continue
    hard = run_isg(T, d, ["shadows.method=hard"], out=os.path.join(T.tmp, "hard.exr"))
    nothing = light_error(hard["out"], d, light)
    for m in METHODS:
        r = run_isg(T, d, [f"shadows.method={m}"], out=os.path.join(T.tmp, f"own-{m}.exr"))
        auto = re.search(r"^\s*shadows\[" + light + r"\]: (\S+)", r["text"], re.M)
        cycles.append({"case": case, "light": light, "method": m, "rmse": light_error(r["out"], d, light),
                       "nothing": nothing, "took": auto.group(1) if auto and m == "auto" else m})
        print("own", case, m, round(cycles[-1]["rmse"] / nothing, 3), flush=True)

# Several lights: the three-light frame against the same frame with the key alone.
speed = {}
for scene in ("contact", "three-lights"):
    case = synth_case(T, scene, a.speed_size, 1, ["--no-refs"], name=f"{scene}-speed")
    best = None
    for _ in range(a.repeat):
        t0 = time.time()
        r = run_isg(T, case, [])
        r["wall_s"] = time.time() - t0
        if best is None or r["wall_s"] < best["wall_s"]:
            best = r
    per_light = {}
    for name, ms in best["passes"].items():
        m = re.search(r"\[([^\]]+)\]", name)
        if m and name.startswith("shadows"):
            per_light[m.group(1)] = per_light.get(m.group(1), 0.0) + ms
    speed[scene] = {"wall_s": best["wall_s"], "gpu_ms": best["gpu_total_ms"], "per_light_ms": per_light,
                    "device": best["device"]}
    print(scene, speed[scene], flush=True)

save("lights.json", {"rows": rows, "cycles": cycles, "speed": speed, "size": a.size, "spp": a.spp})

md = ["# Sun, spot and several lights (issue 52)", "",
      f"isg-synth scenes at {a.size}, references {a.spp} light samples a pixel; `isg run` with "
      "defaults and the method named (glossy reflections on, so the composite is the whole frame). Each light's "
      "`L.softshadow` RMSE against `ref/softshadow_L.exr` over its mask, as a ratio of doing "
      "nothing's (the input's `L.shadow` against the same reference); the composite's RGB RMSE "
      "against `ref/beauty.exr` as a ratio of the input beauty's. Machine: "
      f"{platform.machine()}, {speed['contact']['device']}.", "",
      f"    python3 bench/lights.py --size {a.size} --spp {a.spp} --speed-size {a.speed_size}", "",
      "| scene | method | " + " | ".join(["light: soft / nothing (ratio)"]) + " | composite (ratio) |",
      "|---|---|---|---|"]
for r in rows:
    ls = "; ".join(f"{l}: {v['rmse']:.4f} / {v['nothing']:.4f} (**{v['rmse'] / v['nothing']:.2f}**)"
                   for l, v in r["lights"].items())
    md.append(f"| {r['scene']} | {r['method']} | {ls} | {r['composite']:.4f} / "
              f"{r['composite_nothing']:.4f} (**{r['composite'] / r['composite_nothing']:.2f}**) |")
if cycles:
    md += ["", "## Own Cycles cases", "",
           "Rendered with tools/cases (Blender 3.4 Cycles; the case's README gives its set-up and the "
           "oracle composite). `L.softshadow` RMSE against the converged reference over its mask, and as "
           "a ratio of doing nothing's.", "", "| case | method | RMSE | of doing nothing's |", "|---|---|---|---|"]
    for r in cycles:
        took = f" (took {r['took']})" if r["method"] == "auto" else ""
        md.append(f"| {r['case']} ({r['light']}) | {r['method']}{took} | {r['rmse']:.4f} | **{r['rmse'] / r['nothing']:.2f}** |")
c, t = speed["contact"], speed["three-lights"]
md += ["", f"## Several lights at {a.speed_size} (defaults: method isg; best of {a.repeat})", "",
       "| frame | wall | GPU total | GPU per light (shadow passes) |", "|---|---|---|---|"]
for name, s in (("contact (key alone)", c), ("three-lights (key, sun, fill)", t)):
    pl = ", ".join(f"{l} {ms:.0f} ms" for l, ms in sorted(s["per_light_ms"].items()))
    md.append(f"| {name} | {s['wall_s']:.2f} s | {s['gpu_ms']:.0f} ms | {pl} |")
md += ["", f"Three lights take **{t['wall_s'] / c['wall_s']:.2f}x** the one-light frame's wall time "
       f"({t['gpu_ms'] / max(c['gpu_ms'], 1e-9):.2f}x its GPU time); the frame is read once and "
       "positions, the foreground and the composite are shared; each light has its own tiles, "
       "search and gather."]
open(os.path.join(PAGES, "lights.md"), "w").write("\n".join(md) + "\n")
print("wrote docs/benchmark/lights.md")
