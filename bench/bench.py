#!/usr/bin/env python3
"""First cut of issue 9's benchmark: every effect x method x sample setting on the shared
Cycles cases, GPU time per pass (timestamp queries, best of --repeat) and error against the
case's reference over its mask, next to Cycles' own time-to-error curve (ref/drt/timings.json).
Writes bench/out/runs.json and docs/benchmark.md.

    python3 bench/bench.py [--build build] [--cases ../shared/cases] [--repeat 3]

Not yet here (issue 9 stays open): isg-synth cases, scaling sweeps, the numerical
stability table, memory, the CSSM/VSSM rows."""
import argparse, json, os, platform, re, subprocess, sys, tempfile, time

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--cases", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared", "cases"))
ap.add_argument("--repeat", type=int, default=3)
ap.add_argument("--from-json", action="store_true", help="rewrite the report from bench/out/runs.json")
ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "benchmark.md"))
a = ap.parse_args()
isg = os.path.join(a.build, "cli", "isg")
tmp = tempfile.mkdtemp()

def sh(args):
    return subprocess.run(args, check=True, capture_output=True, text=True).stdout

def run(case, sets):
    """Best GPU time per pass over --repeat runs, and the output path."""
    out = os.path.join(tmp, "o.exr")
    best = None
    for _ in range(a.repeat):
        cmd = [isg, "run", f"{case}/aovs.exr", "--scene", f"{case}/scene.json", "-o", out, "--timings"]
        for s in sets:
            cmd += ["--set", s]
        t = {m.group(1): float(m.group(2)) for m in re.finditer(r"^\s+(\S+)\s+([0-9.]+) ms$", sh(cmd), re.M)}
        best = t if best is None else {k: min(v, best.get(k, v)) for k, v in t.items()}
    return best, out

def rmse(out, ref, mask, channels):
    cmd = [isg, "compare", out, ref, "--json", "--channels", *channels]
    if mask:
        cmd += ["--mask", mask]
    return json.loads(sh(cmd))["all"]["rmse"]

def cycles(case):
    d = json.load(open(f"{case}/ref/drt/timings.json"))
    return [(r["spp"], r["seconds"], r["rmse_vs_ref_mask"]) for r in d["renders"]]

def cycles_time_for(curve, err):
    """Cycles' render time to reach `err`, log-log between its samples (None beyond them)."""
    import math
    for (s0, t0, e0), (s1, t1, e1) in zip(curve, curve[1:]):
        if e1 <= err <= e0:
            f = math.log(err / e0) / math.log(e1 / e0)
            return t0 * (t1 / t0) ** f, s0 * (s1 / s0) ** f
    return None

rows = []
S = ["9", "25", "49", "81"]
plan = []
for c in ("contact", "rowdepth"):
    for s in S:
        for g in S:
            plan.append((c, "shadows", "isg", f"{s}x{g}", [f"shadows.method=isg", f"shadows.search_samples={s}",
                          f"shadows.gather_samples={g}", "reflections.method=none"]))
    for t in ("16", "32", "64"):
        plan.append((c, "shadows", "pcss", f"{t} taps", ["shadows.method=pcss", f"shadows.pcss_taps={t}", "reflections.method=none"]))
    plan.append((c, "shadows", "hard", "-", ["shadows.method=hard", "reflections.method=none"]))
for s in S:
    for g in S:
        plan.append(("gloss", "reflections", "isg", f"{s}x{g}", ["reflections.method=isg", f"reflections.search_samples={s}",
                      f"reflections.gather_samples={g}", "reflections.roughness=0.25", "reflections.roughness_override=true"]))
plan.append(("gloss", "reflections", "blur", "-", ["reflections.method=blur", "reflections.roughness=0.25", "reflections.roughness_override=true"]))
plan.append(("gloss", "reflections", "none", "-", ["reflections.method=none"]))
for m in ("isg", "layered"):
    for n in ("16", "64", "256"):
        plan.append(("dof", "dof", m, f"{n} samples", [f"dof.method={m}", f"dof.samples={n}"]))
plan.append(("dof", "dof", "none", "-", ["dof.method=none"]))

runs_json = os.path.join(os.path.dirname(__file__), "out", "runs.json")
if a.from_json:
    plan = []
    rows = json.load(open(runs_json))
for c, effect, method, setting, sets in plan:
    case = os.path.join(a.cases, c)
    if not os.path.isdir(case):
        continue
    t0 = time.time()
    times, out = run(case, sets)
    wall = (time.time() - t0) / a.repeat
    gpu = sum(v for k, v in times.items() if k.startswith(effect + ".") or k.startswith(effect + "["))
    mask = f"{case}/ref/softshadow_key.exr:mask" if c in ("contact", "rowdepth") else None
    row = {"case": c, "effect": effect, "method": method, "setting": setting, "gpu_ms": gpu,
           "gpu_total_ms": times.get("total", 0.0), "gpu_passes_ms": times, "wall_s": wall,
           "composite_rmse": rmse(out, f"{case}/ref/beauty.exr", mask, ["R", "G", "B"])}
    if effect == "shadows":
        row["effect_rmse"] = rmse(out, f"{case}/ref/softshadow_key.exr", "mask", ["key.softshadow"]) if method != "hard" else None
    rows.append(row)
    print(c, effect, method, setting, f"{gpu:.1f} ms", f"{row['composite_rmse']:.5f}", file=sys.stderr)

os.makedirs(os.path.join(os.path.dirname(__file__), "out"), exist_ok=True)
if not a.from_json:
    json.dump(rows, open(runs_json, "w"), indent=1)

dev = re.search(r"device: (.*)", sh([isg, "run", f"{a.cases}/contact/aovs.exr", "--scene", f"{a.cases}/contact/scene.json",
                                      "-o", os.path.join(tmp, "d.exr"), "--timings"]))
L = ["# Benchmark: speed against error", "",
     f"Generated by `python3 bench/bench.py` on {platform.node()} ({os.cpu_count()} cores), "
     f"device {dev.group(1) if dev else '?'}; GPU time from timestamp queries, best of {a.repeat}; "
     "error = RGB RMSE of the composite against the case's converged Cycles reference over the mask "
     "`ref/drt/timings.json` names. Cycles' time is its own render time (path tracing only) on the same "
     "kind of machine; 'Cycles reaches it' interpolates its curve log-log.", "",
     "Effects a row does not set run at their defaults (soft shadows isg, glossy reflections isg, "
     "no depth of field); the `hard` / `none` rows are each effect's doing-nothing baseline.", "",
     "Companion pages: [the shadow-map methods against isg](benchmark/shadowmap_methods.md) (`python3 bench/shadowmap_methods.py`, shared and isg-synth cases) and [scaling](benchmark/scaling.md) (`python3 bench/scaling.py`: pixels, samples, shadow-map size, light radius, tiles). Still to come (issue 9): the stability table and per-run memory. `python3 bench/bench.py --from-json` rewrites this page and its plots from bench/out/runs.json without re-running.", ""]
COLOURS = {"isg": "#d62728", "pcss": "#1f77b4", "blur": "#2ca02c", "layered": "#9467bd",
           "hard": "#7f7f7f", "none": "#7f7f7f"}

def svg_plot(path, title, rs, curve):
    """Error (log) against time (log): our runs as points (all passes' GPU time), Cycles' render
    time-to-error as a line."""
    import math
    W, H, m = 560, 360, 56
    pts = [(max(r["gpu_total_ms"], 1e-3) / 1000.0, r["composite_rmse"], r["method"]) for r in rs]
    xs = [p[0] for p in pts] + [t for _, t, _ in curve]
    ys = [p[1] for p in pts] + [e for _, _, e in curve]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    X = lambda t: m + (math.log10(t) - x0) / (x1 - x0) * (W - 1.5 * m)
    Y = lambda e: H - m - (math.log10(e) - y0) / (y1 - y0) * (H - 1.6 * m)
    o = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="11">',
         f'<rect width="{W}" height="{H}" fill="white"/>',
         f'<text x="{W/2}" y="16" text-anchor="middle" font-size="13">{title}</text>']
    for k in range(x0, x1 + 1):
        o.append(f'<line x1="{X(10**k):.1f}" y1="{Y(10**y0):.1f}" x2="{X(10**k):.1f}" y2="{Y(10**y1):.1f}" stroke="#ddd"/>')
        o.append(f'<text x="{X(10**k):.1f}" y="{H - m + 16}" text-anchor="middle">{10**k:g} s</text>')
    for k in range(y0, y1 + 1):
        o.append(f'<line x1="{X(10**x0):.1f}" y1="{Y(10**k):.1f}" x2="{X(10**x1):.1f}" y2="{Y(10**k):.1f}" stroke="#ddd"/>')
        o.append(f'<text x="{m - 6}" y="{Y(10**k) + 4:.1f}" text-anchor="end">{10**k:g}</text>')
    o.append(f'<text x="{W/2}" y="{H - 12}" text-anchor="middle">time (isg: GPU time of all passes on the device; Cycles: render time)</text>')
    o.append(f'<text x="14" y="{H/2}" transform="rotate(-90 14 {H/2})" text-anchor="middle">RMSE of the composite</text>')
    line = " ".join(f"{X(t):.1f},{Y(e):.1f}" for _, t, e in curve)
    o.append(f'<polyline points="{line}" fill="none" stroke="black" stroke-width="1.5"/>')
    for spp, t, e in curve:
        o.append(f'<text x="{X(t) + 4:.1f}" y="{Y(e) - 4:.1f}" font-size="9">{spp} spp</text>')
    for t, e, meth in pts:
        o.append(f'<circle cx="{X(t):.1f}" cy="{Y(e):.1f}" r="3.5" fill="{COLOURS.get(meth, "#ff7f0e")}" fill-opacity="0.8"/>')
    ly = 30
    for meth in ["Cycles"] + sorted({p[2] for p in pts}):
        col = "black" if meth == "Cycles" else COLOURS.get(meth, "#ff7f0e")
        o.append(f'<rect x="{W - m - 40}" y="{ly - 8}" width="10" height="10" fill="{col}"/><text x="{W - m - 26}" y="{ly + 1}">{meth}</text>')
        ly += 14
    o.append("</svg>")
    open(path, "w").write("\n".join(o))

plot_dir = os.path.join(os.path.dirname(a.out), "benchmark")
os.makedirs(plot_dir, exist_ok=True)
for c in ("contact", "rowdepth", "gloss", "dof"):
    rs = [r for r in rows if r["case"] == c]
    if not rs:
        continue
    curve = cycles(os.path.join(a.cases, c))
    svg_plot(os.path.join(plot_dir, f"{c}.svg"), f"{c}: error against time", rs, curve)
    L += [f"## {c}", "", f"![{c}: error against time](benchmark/{c}.svg)", "", "Cycles: " + ", ".join(f"{s} spp {t:.2f} s → {e:.5f}" for s, t, e in curve), "",
          "| effect | method | setting | effect GPU ms | all passes GPU ms | composite RMSE | effect RMSE | Cycles reaches it at |",
          "|---|---|---|---|---|---|---|---|"]
    for r in rs:
        ct = cycles_time_for(curve, r["composite_rmse"])
        eff = r.get("effect_rmse")
        L.append(f"| {r['effect']} | {r['method']} | {r['setting']} | {r['gpu_ms']:.1f} | {r['gpu_total_ms']:.1f} | {r['composite_rmse']:.5f} | "
                 f"{'' if eff is None else f'{eff:.5f}'} | {'beyond its curve' if ct is None else f'{ct[1]:.0f} spp, {ct[0]:.2f} s'} |")
    L.append("")
open(a.out, "w").write("\n".join(L))
print("wrote", a.out, file=sys.stderr)
