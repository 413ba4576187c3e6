#!/usr/bin/env python3
"""Issue 18's speed table: `isg run` on a 1920x1080 isg-synth contact frame (24 channels) against
`oiiotool in.exr -o out.exr` (the I/O floor), all in one session, alternating the commands so a
machine's load swings hit each alike; best wall time of --repeat runs each. Rows: doing nothing
(shadows hard, reflections none), the default preset, the default preset with dof.method=layered.
Per-pass GPU time (timestamp queries) and each gather pass's samples/s against the roofline
(`isg roofline`, measured by --timings on the same device). --baseline BIN adds the same rows for
an older isg binary (its isg-exrcheck beside it), e.g. a build of the commit before a change.

    python3 bench/speed.py [--build build] [--size 1920x1080] [--repeat 3] [--baseline OLD/isg]

Writes bench/out/speed.json and docs/benchmark/speed.md."""
import argparse, os, re, subprocess, sys, time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
from common import PAGES, Tools, load, parse_timings, save, synth_case

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--size", default="1920x1080")
ap.add_argument("--repeat", type=int, default=3)
ap.add_argument("--baseline", default="", help="an older isg binary to measure beside this one")
ap.add_argument("--from-json", action="store_true")
a = ap.parse_args()

ROWS = [("doing nothing", ["shadows.method=hard", "reflections.method=none"]),
        ("default preset", []),
        ("default + dof layered", ["dof.method=layered"])]


def timed(cmd):
    t0 = time.time()
    p = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return time.time() - t0, p.stdout


def nominal_samples(isg):
    """The default preset's lattice per effect: search + gather samples a pixel (`isg params`)."""
    v = dict(re.findall(r"^(\S+)\s+(\S+)", subprocess.run([isg, "params"], check=True, capture_output=True,
                                                       text=True).stdout, re.M))
    return {e: int(v[f"{e}.search_samples"]) + int(v[f"{e}.gather_samples"]) for e in ("shadows", "reflections")}


def measure():
    T = Tools(a.build)
    w, h = a.size.split("x")
    d = synth_case(T, "contact", a.size, 1, ["--no-refs"], f"contact-{a.size}")
    aovs = f"{d}/aovs.exr"
    bins = [("this build", T.isg)] + ([("baseline", a.baseline)] if a.baseline else [])
    best = {}
    texts = {}
    def command(binary, sets, timings):
        cmd = [binary, "run", aovs, "--scene", f"{d}/scene.json", "-o", f"{T.tmp}/o.exr"]
        for x in sets:
            cmd += ["--set", x]
        return cmd + (["--timings"] if timings else [])
    # Wall times without --timings (which also measures the roofline); then one --timings run
    # of each for the stages, the passes and the gather shares.
    for _ in range(a.repeat):
        s, _ = timed(["oiiotool", aovs, "-o", f"{T.tmp}/copy.exr"])
        best["oiiotool"] = min(best.get("oiiotool", 1e9), s)
        for label, binary in bins:
            for row, sets in ROWS:
                s, _ = timed(command(binary, sets, False))
                best[f"{label}|{row}"] = min(best.get(f"{label}|{row}", 1e9), s)
    for label, binary in bins:
        for row, sets in ROWS:
            texts[f"{label}|{row}"] = timed(command(binary, sets, True))[1]
    runs = []
    for label, _ in bins:
        for row, sets in ROWS:
            key = f"{label}|{row}"
            t = parse_timings(texts[key])
            wall = re.search(r"^wall: (.*)$", t["text"], re.M)
            # "N pixels, S samples (s a pixel; k taps a sample), X M samples/s, Y M taps/s = Z% of the
            # roofline"; older builds printed no taps (one a sample) and, before the quad search,
            # "N pixels x s samples".
            gathers = re.findall(r"^(\S+): (\d+) pixels(?:, \d+ samples \(([0-9.]+) a pixel(?:; (\d+) taps? a sample)?\)"
                                 r"| x (\d+) samples), ([0-9.]+) M samples/s(?:, [0-9.]+ M taps/s)? = ([0-9.]+)% of the "
                                 r"roofline \(([0-9.]+) M taps/s", t["text"], re.M)
            gathers = [(g[0], g[1], g[2] or g[4], g[5], g[6], g[7], g[3] or "1") for g in gathers]
            runs.append({"binary": label, "row": row, "sets": sets, "wall_s": best[key],
                         "ratio": best[key] / best["oiiotool"], "passes": t["passes"],
                         "gpu_ms": t["gpu_total_ms"], "stages": wall.group(1) if wall else "",
                         "gathers": [{"pass": g[0], "pixels": int(g[1]), "samples": float(g[2]),
                                      "msamples_s": float(g[3]), "share": float(g[4]),
                                      "roofline_mtaps_s": float(g[5]), "taps_per_sample": int(g[6])}
                                     for g in gathers],
                         "device": t["device"]})
    return {"size": a.size, "repeat": a.repeat, "oiiotool_s": best["oiiotool"], "runs": runs,
            "nominal": nominal_samples(T.isg), "load": os.getloadavg()[0]}


def page(r):
    L = [f"# Speed: `isg run` against its own file I/O ({r['size']})", "",
         "Generated by `python3 bench/speed.py` (issue 18). isg-synth `contact` at "
         f"{r['size']}, 24 channels; best wall time of {r['repeat']} runs of each command, the "
         "commands alternated in one session; `oiiotool in.exr -o out.exr` is the I/O floor: "
         f"**{r['oiiotool_s']:.2f} s**. Device: {r['runs'][0]['device']}. Load average at the end: "
         f"{r['load']:.1f}.", "",
         "The shadow-map methods (pcss, vssm, cssm) dispatch by dispatch, their pipelines' cold "
         "compile and a large-penumbra series: [shadowmap_speed.md](shadowmap_speed.md) "
         "(`python3 bench/shadowmap_speed.py`, issue 51).", "",
         "| binary | run | wall | × oiiotool | GPU total | stages of one --timings run (ms) |", "|---|---|---|---|---|---|"]
    for x in r["runs"]:
        L.append(f"| {x['binary']} | {x['row']} | {x['wall_s']:.2f} s | {x['ratio']:.2f}× | "
                 f"{x['gpu_ms']:.0f} ms | {x['stages']} |")
    L += ["", "## GPU time per pass (timestamp queries)", ""]
    for x in r["runs"]:
        L.append(f"- {x['binary']}, {x['row']}: " +
                 ", ".join(f"{k} {v:.1f} ms" for k, v in x["passes"].items()))
    L += ["", "## Gather passes against the roofline", "",
          "Taps/s of each gather pass as a share of a plain cross-bilateral gather's taps/s on the "
          "same device, measured in the same run (`isg run --timings`; the yardstick is [the "
          "roofline page](roofline.md)). A tap is the roofline's unit: one 16-byte texel read with "
          "its own range weight. The samples are the lattice samples a pass took in all, search "
          "and gather, over its GPU time (reflections.isg searches once per 2×2 quad and gathers "
          "wide lobes once per 4×4 block, in dispatches of their own: its time is theirs, "
          "reflections.isg.search, .wide and .own, with the pixels'; shadows.isg's likewise "
          ".reach, .quads and .own, with the pixels', where a build before 8737e69 ran it as one "
          "dispatch); a sample of reflections.isg is one point tap (two "
          "16-byte texels: colour and distance, position and normal), a sample of shadows.isg "
          "four bilinear taps (binaries that printed no taps counted samples). The share falls as "
          "the samples a pixel fall (the per-pixel work stays): *nominal lattice* is the time the "
          "roofline's gather would take for the same pixels at the preset's full lattice (search "
          "plus gather samples a pixel, as many taps each), over the pass's time (all its "
          "dispatches), i.e. the "
          "share times nominal samples / samples taken.", "",
          "| binary | run | pass | pixels | samples a pixel | taps a sample | M samples/s | M taps/s | "
          "roofline M taps/s | share | nominal lattice |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    nominal = r.get("nominal", {})
    for x in r["runs"]:
        for g in x["gathers"]:
            k = g.get("taps_per_sample", 1)
            n = nominal.get(g["pass"].split(".")[0])
            eff = f"{n} samples: {g['share'] * n / g['samples']:.0f}%" if n and g["samples"] > 0 else "-"
            L.append(f"| {x['binary']} | {x['row']} | {g['pass']} | {g['pixels']} | {g['samples']:.1f} | "
                     f"{k} | {g['msamples_s']:.1f} | {g['msamples_s'] * k:.1f} | "
                     f"{g['roofline_mtaps_s']:.0f} | {g['share']:.0f}% | {eff} |")
    return "\n".join(L) + "\n"


r = load("speed.json") if a.from_json else measure()
save("speed.json", r)
os.makedirs(PAGES, exist_ok=True)
open(os.path.join(PAGES, "speed.md"), "w").write(page(r))
print(page(r))
