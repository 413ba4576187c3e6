#!/usr/bin/env python3
"""The benchmark (issue 9), one command for every page:

    python3 bench/bench.py [--build build] [--cases ../shared/cases] [--repeat 2]
                           [--skip stability,shadowmap,shadowcases,scaling,roofline,speed] [--from-json]

1. Speed against error, this page (docs/benchmark.md): every effect x method x setting on every
   ../shared/cases/* that has ref/drt/timings.json and on isg-synth contact, stack, gloss and dof
   generated on the fly. Per run: GPU time per pass (timestamp queries, best of --repeat), wall
   time, peak GPU (device-local + staging, counted at every allocation) and host (resident)
   memory, and RMSE / PSNR / SSIM / max error of the composite against the case's beauty
   reference and of the effect's own channel against its reference, over the case's mask. Next
   to them the alternative a user has: the renderer with more samples (Cycles' curve from
   ref/drt/timings.json; for isg-synth cases its own distribution ray tracer at 1-16 spp). A
   plot per case (docs/benchmark/<case>.svg), an error heat-map per case and method
   (docs/benchmark/heat/), every run in bench/out/runs.json.
2. bench/stability.py  -> docs/benchmark/stability.md (far world, depth range, grazing, 4096²
   maps, half floats, NaN/Inf: every method's error on each)
3. bench/shadowmap_methods.py -> docs/benchmark/shadowmap_methods.md
   bench/shadow_cases.py -> docs/benchmark/shadow_cases.md (every shadow method on every Cycles
   case with a soft-shadow reference, shared and the repository's own, from P and from Z)
4. bench/scaling.py    -> docs/benchmark/scaling.md (pixels, samples, map size, kernel radius)
5. bench/roofline.py   -> docs/benchmark/roofline.md (a plain cross-bilateral gather's taps/s,
   the yardstick for the gather passes)
6. bench/speed.py      -> docs/benchmark/speed.md (1080p `isg run` against `oiiotool in -o out`,
   per-pass GPU time, each gather pass's share of the roofline)

--from-json rewrites every page from bench/out/*.json without running anything."""
import argparse, json, math, os, platform, re, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import (DOCS, HERE, PAGES, SHARED_CASES, Tools, compare, exr_attribute, load, run_isg,
                    save, sh, synth_case)

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--cases", default=SHARED_CASES)
ap.add_argument("--repeat", type=int, default=2)
ap.add_argument("--synth-size", default="480x270")
ap.add_argument("--synth-spp", type=int, default=256, help="isg-synth reference samples per pixel")
ap.add_argument("--only", default="", help="comma-separated case names (e.g. contact,synth-gloss): "
                "run only these, for a quick look (the page then shows only them)")
ap.add_argument("--skip", default="", help="comma-separated: pareto, stability, shadowmap, shadowcases, scaling, roofline, speed")
ap.add_argument("--from-json", action="store_true", help="rewrite the pages from bench/out/*.json")
a = ap.parse_args()
skip = set(filter(None, a.skip.split(",")))
t = Tools(a.build)

# ---- the cases ----------------------------------------------------------------------------------


def shared_cases():
    """Every shared case with a Cycles curve: its effect, mask, curve and oracle error."""
    out = []
    for name in sorted(os.listdir(a.cases)) if os.path.isdir(a.cases) else []:
        d = os.path.join(a.cases, name)
        tj = os.path.join(d, "ref", "drt", "timings.json")
        if not os.path.exists(tj):
            continue
        drt = json.load(open(tj))
        readme = open(os.path.join(d, "README.md")).read() if os.path.exists(os.path.join(d, "README.md")) else ""
        if os.path.exists(os.path.join(d, "ref", "softshadow_key.exr")):
            effect = "shadows"
        elif "refl.weight" in drt.get("mask", ""):
            effect = "reflections"
        else:
            effect = "dof"
        m = re.search(r"Oracle composite:.*?scores RMSE ([0-9.]+) over the mask", readme)
        out.append({"name": name, "label": f"shared {name}", "dir": d, "effect": effect,
                    "mask_rule": drt.get("mask", ""), "oracle": float(m.group(1)) if m else None,
                    "curve_name": "Cycles",
                    "curve": [(r["spp"], r["seconds"], r["rmse_vs_ref_mask"]) for r in drt["renders"]],
                    "roughness": re.search(r"roughness ([0-9.]+) \(roughness_ref\)", readme)})
    return out


def case_mask(c):
    """The mask its curve was measured over, as `isg compare --mask` takes it."""
    d, rule = c["dir"], c.get("mask_rule", "")
    if c.get("synth"):
        return f"{d}/ref/beauty.exr:mask"
    if rule.startswith("ref/softshadow_key.exr"):
        return f"{d}/ref/softshadow_key.exr:mask"
    if "refl.weight" in rule:
        # foreground (alpha > 0.5, Z < 1e9) and refl.weight luminance > 0.05, built by oiiotool:
        # each test is a step (x − edge)·1e30 clamped to [0, 1], the three multiplied.
        m = os.path.join(t.tmp, f"{c['name']}-mask.exr")
        aov = f"{d}/aovs.exr"
        sh(["oiiotool", aov, "--ch", "refl.weight.R,refl.weight.G,refl.weight.B",
            "--chsum:weight=0.2126,0.7152,0.0722", "--subc", "0.05", "--mulc", "1e30", "--clamp:min=0:max=1",
            aov, "--ch", "A", "--subc", "0.5", "--mulc", "1e30", "--clamp:min=0:max=1", "--mul",
            aov, "--ch", "Z", "--mulc", "-1", "--addc", "1e9", "--mulc", "1e30", "--clamp:min=0:max=1", "--mul",
            "--chnames", "mask", "-d", "float", "-o", m])
        return f"{m}:mask"
    return None  # every pixel


def synth_cases():
    """isg-synth cases with the ray tracer's own curve: its beauty at 1, 4, 16 spp (render time
    from the EXR header) against the --synth-spp reference."""
    out = []
    for scene, effect in (("contact", "shadows"), ("stack", "shadows"), ("gloss", "reflections"), ("dof", "dof")):
        if a.only and f"synth-{scene}" not in a.only.split(","):
            continue
        d = synth_case(t, scene, a.synth_size, a.synth_spp)
        curve = []
        for spp in (n for n in (1, 4, 16) if n < a.synth_spp):
            e = synth_case(t, scene, a.synth_size, spp)
            secs = float(exr_attribute(f"{e}/ref/beauty.exr", "isg:render_seconds") or "nan")
            err = compare(t, f"{e}/ref/beauty.exr", f"{d}/ref/beauty.exr", ["R", "G", "B"], f"{d}/ref/beauty.exr:mask")
            curve.append((spp, secs, err["rmse"]))
        out.append({"name": f"synth-{scene}", "label": f"isg-synth {scene} {a.synth_size}", "dir": d,
                    "effect": effect, "synth": True, "oracle": None, "curve": curve,
                    "curve_name": f"isg-synth ray tracer (CPU, {os.cpu_count()} threads)"})
    return out


def settings(c):
    """(method, setting, --set list) for the case's effect; the others off or at defaults."""
    S = ["9", "25", "49"]
    rows = []
    if c["effect"] == "shadows":
        off = ["reflections.method=none"]
        rows.append(("hard", "-", ["shadows.method=hard", *off]))
        rows += [("isg", f"{s}x{g}", ["shadows.method=isg", f"shadows.search_samples={s}",
                                      f"shadows.gather_samples={g}", *off]) for s in S for g in S]
        rows += [("pcss", f"{n} taps", ["shadows.method=pcss", f"shadows.pcss_taps={n}", *off]) for n in ("16", "32", "64")]
        rows += [("cssm", f"M {m}, {f}", ["shadows.method=cssm", f"shadows.cssm_order={m}", f"shadows.cssm_filter={f}", *off])
                 for m, f in (("8", "sat"), ("16", "sat"), ("8", "mipmap"))]
        rows += [("vssm", "m 5, H 2", ["shadows.method=vssm", *off]),
                 ("vssm", "m 1, H 0 (VSM leaves)", ["shadows.method=vssm", "shadows.vssm_m=1", "shadows.vssm_m_wide=1", "shadows.vssm_h=0",
                                                     "shadows.vssm_leaf_taps=0", *off])]
    elif c["effect"] == "reflections":
        r = c.get("roughness")
        rough = [f"reflections.roughness={r.group(1)}", "reflections.roughness_override=true"] if r else []
        rows.append(("none", "-", ["reflections.method=none"]))
        rows += [("isg", f"{s}x{g}", ["reflections.method=isg", f"reflections.search_samples={s}",
                                      f"reflections.gather_samples={g}", *rough]) for s in S for g in S]
        rows.append(("blur", "-", ["reflections.method=blur", *rough]))
    else:
        # isg-synth's ref/dof.exr is the AOV beauty through the lens: the other effects off.
        off = ["shadows.method=hard", "reflections.method=none"] if c.get("synth") else []
        rows.append(("none", "-", ["dof.method=none", *off]))
        rows += [(m, f"{n} samples", [f"dof.method={m}", f"dof.samples={n}", *off])
                 for m in ("isg", "layered") for n in ("16", "64", "256")]
    return rows


def effect_ref(c):
    """(reference file, channels, mask) for the effect's own output, or None."""
    d = c["dir"]
    if c["effect"] == "shadows":
        return f"{d}/ref/softshadow_key.exr", ["key.softshadow"], "mask"
    if c.get("synth") and c["effect"] == "reflections":
        return f"{d}/ref/glossy.exr", ["refl.glossy.R", "refl.glossy.G", "refl.glossy.B"], "mask"
    if c.get("synth") and c["effect"] == "dof":
        return f"{d}/ref/dof.exr", ["R", "G", "B"], "mask"
    return None


PREFIX = {"shadows": ("shadows.", "composite[key]"), "reflections": ("reflections.", "composite[reflections]"),
          "dof": ("dof.",)}


def pareto_runs():
    cases = shared_cases() + synth_cases()
    if a.only:
        cases = [c for c in cases if c["name"] in a.only.split(",")]
    rows = []
    for c in cases:
        mask = case_mask(c)
        er = effect_ref(c)
        for method, setting, sets in settings(c):
            r = run_isg(t, c["dir"], sets, repeat=a.repeat)
            gpu = sum(v for k, v in r["passes"].items() if k.startswith(PREFIX[c["effect"]]))
            row = {"case": c["label"], "effect": c["effect"], "method": method, "setting": setting, "sets": sets,
                   "device": r["device"], "gpu_ms": gpu, "gpu_total_ms": r["gpu_total_ms"], "passes": r["passes"],
                   "wall_s": r["wall_s"], "gpu_mib": r.get("gpu_mib"), "staging_mib": r.get("staging_mib"),
                   "host_mib": r.get("host_mib"),
                   "composite": compare(t, r["out"], f"{c['dir']}/ref/beauty.exr", ["R", "G", "B"], mask)}
            if er and method in ("hard", "none") and c["effect"] in INPUT_OF:
                row["effect_err"] = compare_input(r["out"], er, c["effect"])
            elif er:
                row["effect_err"] = compare(t, r["out"], er[0], er[1], er[2])
            rows.append(row)
            print(c["label"], method, setting, f"{gpu:.1f} ms", f"{row['composite']['rmse']:.5f}", file=sys.stderr, flush=True)
        heatmaps(c, [r for r in rows if r["case"] == c["label"]], mask, er)
    save("runs.json", {"machine": machine(), "commit": commit(), "cases": [{k: v for k, v in c.items() if k != "roughness"} for c in cases],
                       "runs": rows})


# Doing nothing, measured on the effect's channel: the input channel it replaces.
INPUT_OF = {"shadows": ["key.shadow"], "reflections": ["refl.R", "refl.G", "refl.B"]}


def compare_input(out, er, effect, **heat):
    """The input's hard shadow / sharp reflection against the effect's reference."""
    tmp = os.path.join(t.tmp, "input.exr")
    sh(["oiiotool", out, "--ch", ",".join(f"{w}={h}" for w, h in zip(er[1], INPUT_OF[effect])), "-o", tmp])
    return compare(t, tmp, er[0], er[1], er[2], **heat)


def heatmaps(c, rows, mask, er):
    """Per method, its best run's error picture, on one scale per case (3x doing nothing's RMSE)."""
    os.makedirs(os.path.join(PAGES, "heat"), exist_ok=True)
    base = next(r for r in rows if r["method"] in ("hard", "none"))
    use_effect = er is not None
    scale = 3 * (base["effect_err"] if use_effect else base["composite"])["rmse"]
    for method in dict.fromkeys(r["method"] for r in rows):
        best = min((r for r in rows if r["method"] == method), key=lambda r: r["composite"]["rmse"])
        r = run_isg(t, c["dir"], best["sets"])
        path = os.path.join(PAGES, "heat", f"{c['name']}-{method}.jpg")
        if use_effect and method in ("hard", "none") and c["effect"] in INPUT_OF:
            compare_input(r["out"], er, c["effect"], heatmap=path, heatmap_max=scale)
        elif use_effect:
            compare(t, r["out"], er[0], er[1], er[2], heatmap=path, heatmap_max=scale)
        else:
            compare(t, r["out"], f"{c['dir']}/ref/beauty.exr", ["R", "G", "B"], mask, heatmap=path, heatmap_max=scale)
        best["heatmap"] = os.path.relpath(path, DOCS)
        best["heatmap_of"] = "effect" if use_effect else "composite"
        best["heatmap_max"] = scale


def commit():
    try:
        return sh(["git", "-C", HERE, "rev-parse", "--short", "HEAD"]).strip()
    except Exception:
        return "?"


def machine():
    cpu = "?"
    try:
        cpu = re.search(r"model name\s*:\s*(.*)", open("/proc/cpuinfo").read()).group(1)
    except Exception:
        pass
    return f"{platform.node()}: {cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


# ---- the report ---------------------------------------------------------------------------------

COLOURS = {"isg": "#d62728", "pcss": "#1f77b4", "cssm": "#17becf", "vssm": "#bcbd22", "blur": "#2ca02c",
           "layered": "#9467bd", "hard": "#7f7f7f", "none": "#7f7f7f"}


def curve_at(curve, err):
    """The renderer's (seconds, spp) reaching `err`, log-log between its samples; None beyond."""
    for (s0, t0, e0), (s1, t1, e1) in zip(curve, curve[1:]):
        if 0 < e1 <= err <= e0 and e1 < e0:
            f = math.log(err / e0) / math.log(e1 / e0)
            return t0 * (t1 / t0) ** f, s0 * (s1 / s0) ** f
    return None


def svg_plot(path, title, rows, curve, curve_name):
    """Composite error (log) against time (log): our runs as points (GPU time of all passes), the
    renderer's time-to-error as a line."""
    W, H, m = 600, 380, 60
    pts = [(max(r["gpu_total_ms"], 1e-3) / 1000.0, r["composite"]["rmse"], r["method"]) for r in rows]
    xs = [p[0] for p in pts] + [c[1] for c in curve]
    ys = [p[1] for p in pts] + [c[2] for c in curve]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    x1, y1 = max(x1, x0 + 1), max(y1, y0 + 1)
    X = lambda v: m + (math.log10(v) - x0) / (x1 - x0) * (W - 1.5 * m)
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
    o.append(f'<text x="{W/2}" y="{H - 12}" text-anchor="middle">time (isg: GPU time of all passes; renderer: its render time)</text>')
    o.append(f'<text x="14" y="{H/2}" transform="rotate(-90 14 {H/2})" text-anchor="middle">RMSE of the composite</text>')
    o.append('<polyline points="' + " ".join(f"{X(c[1]):.1f},{Y(c[2]):.1f}" for c in curve) +
             '" fill="none" stroke="black" stroke-width="1.5"/>')
    for spp, secs, e in curve:
        o.append(f'<text x="{X(secs) + 4:.1f}" y="{Y(e) - 4:.1f}" font-size="9">{spp} spp</text>')
    for x, e, meth in pts:
        o.append(f'<circle cx="{X(x):.1f}" cy="{Y(e):.1f}" r="3.5" fill="{COLOURS.get(meth, "#ff7f0e")}" fill-opacity="0.8"/>')
    ly = 30
    for meth in [curve_name] + list(dict.fromkeys(p[2] for p in pts)):
        col = "black" if meth == curve_name else COLOURS.get(meth, "#ff7f0e")
        o.append(f'<rect x="{W - m - 150}" y="{ly - 8}" width="10" height="10" fill="{col}"/>'
                 f'<text x="{W - m - 136}" y="{ly + 1}">{meth}</text>')
        ly += 14
    o.append("</svg>")
    open(path, "w").write("\n".join(o))


def pareto(rows):
    """Runs no other run beats on both GPU time and composite error."""
    return {id(r) for r in rows if not any(
        q["gpu_total_ms"] <= r["gpu_total_ms"] and q["composite"]["rmse"] < r["composite"]["rmse"] for q in rows)}


def fmt(e):
    return f"{e['rmse']:.5f} / {e['psnr']:.1f} / {e['ssim']:.4f} / {e['max_abs']:.3f}" if e else ""


def report():
    data = load("runs.json")
    runs, cases = data["runs"], data["cases"]
    devices = sorted({r["device"] for r in runs})
    L = ["# Benchmark: speed against error", "",
         "Generated by `python3 bench/bench.py` (this page, its plots and heat-maps, and the three "
         "companion pages; `--from-json` rewrites them from bench/out/ without running). "
         f"Runs made at commit {data.get('commit', '?')}. Machine: {data['machine']}. Device of every isg figure: {', '.join(devices)}. No real GPU was "
         "lent to the session that produced these figures (`device` status: none for this task); on "
         "a machine with one, the same command names it here.", "",
         "- **isg time**: GPU time from timestamp queries, best of the runs; *effect* = the effect's "
         "own passes (and its composite pass), *all* = every pass of the run. *wall* = the whole "
         "`isg run` process (read, device start-up, upload, GPU, write), mean of the runs.",
         "- **memory**: peak GPU memory counted at every allocation (device-local + staging) and "
         "the process's peak resident set.",
         "- **error**: RMSE / PSNR (dB, peak 1) / SSIM / max |error|, over the mask the case's curve "
         "uses: *composite* = RGB against ref/beauty.exr; *effect* = the effect's own channel "
         "against its reference (key.softshadow, refl.glossy, the lens image) where the case has one.",
         "- **the alternative**: the renderer with more samples. Shared cases: Cycles' render time "
         "(path tracing only, same kind of 2-core machine) from ref/drt/timings.json. isg-synth "
         "cases: its CPU distribution ray tracer's beauty at 1, 4, 16 spp against its own reference "
         "(render time from the EXR header). *renderer reaches it at*: its curve interpolated log-log "
         "at the run's composite error.",
         "- Rows set only their effect; shadow and dof rows turn glossy reflections off (on "
         "lavapipe they cost seconds and are measured on the gloss cases); isg-synth dof rows also "
         "use hard shadows, so the lens image compares with ref/dof.exr. `hard` / `none` rows are "
         "doing nothing. ★ = on the Pareto front (no run both faster and lower in composite error).", "",
         "Companion pages: [numerical stability](benchmark/stability.md) · "
         "[shadow-map methods against isg](benchmark/shadowmap_methods.md) · "
         "[shadow methods on more Cycles cases](benchmark/shadow_cases.md) · "
         "[sun, spot and several lights](benchmark/lights.md) · "
         "[Blender's Defocus node against isg](benchmark/dof_blender.md) · "
         "[scaling](benchmark/scaling.md) · [roofline gather](benchmark/roofline.md) · [speed against file I/O](benchmark/speed.md) · [the same on a GPU (H200, H100)](benchmark/speed-gpu.md).", "",
         "## Summary: per case, isg's best run and its fastest good one, against the renderer", "",
         "*best*: the lowest composite error of any method and setting; *fastest ≤ ½*: the fastest run "
         "that at least halves doing nothing's composite error. *gap closed*: (nothing − run) / "
         "(nothing − oracle), the oracle being the case README's composite from the reference effect.", "",
         "| case | effect | doing nothing | oracle | best: method, setting | GPU ms | RMSE | of nothing | gap closed | renderer reaches it at | fastest ≤ ½: method, setting | GPU ms | RMSE | renderer reaches it at |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        rs = [r for r in runs if r["case"] == c["label"]]
        if not rs:
            continue
        base = next(r for r in rs if r["method"] in ("hard", "none"))["composite"]["rmse"]
        ours = [r for r in rs if r["method"] not in ("hard", "none")]
        best = min(ours, key=lambda r: r["composite"]["rmse"])
        good = [r for r in ours if r["composite"]["rmse"] <= 0.5 * base]
        fast = min(good, key=lambda r: r["gpu_total_ms"]) if good else None

        def at(r):
            x = curve_at(c["curve"], r["composite"]["rmse"])
            return "beyond its curve" if x is None else f"{x[1]:.0f} spp, {x[0]:.2f} s"
        e = best["composite"]["rmse"]
        gap = f"{(base - e) / (base - c['oracle']) * 100:.0f}%" if c.get("oracle") else "-"
        row = (f"| {c['label']} | {c['effect']} | {base:.5f} | {c['oracle'] or '-'} | {best['method']}, {best['setting']} | "
               f"{best['gpu_total_ms']:.0f} | {e:.5f} | {e / base:.2f} | {gap} | {at(best)} | ")
        row += (f"{fast['method']}, {fast['setting']} | {fast['gpu_total_ms']:.0f} | {fast['composite']['rmse']:.5f} | {at(fast)} |"
                if fast else "none halves it | | | |")
        L.append(row)
    L.append("")
    os.makedirs(PAGES, exist_ok=True)
    for c in cases:
        rs = [r for r in runs if r["case"] == c["label"]]
        if not rs:
            continue
        svg = os.path.join(PAGES, f"{c['name']}.svg")
        svg_plot(svg, f"{c['label']}: error against time", rs, c["curve"], c["curve_name"])
        front = pareto(rs)
        L += [f"## {c['label']}", "", f"![{c['label']}: error against time](benchmark/{c['name']}.svg)", "",
              f"{c['curve_name']}: " + ", ".join(f"{s} spp {x:.2f} s → {e:.5f}" for s, x, e in c["curve"]) +
              (f". Oracle composite (case README): {c['oracle']}." if c.get("oracle") else "."), "",
              "| method | setting | GPU ms effect / all | wall s | GPU MiB (+staging) | host MiB | composite RMSE / PSNR / SSIM / max | effect RMSE / PSNR / SSIM / max | renderer reaches it at |",
              "|---|---|---|---|---|---|---|---|---|"]
        for r in rs:
            at = curve_at(c["curve"], r["composite"]["rmse"])
            star = " ★" if id(r) in front else ""
            L.append(f"| {r['method']}{star} | {r['setting']} | {r['gpu_ms']:.1f} / {r['gpu_total_ms']:.1f} | {r['wall_s']:.2f} | "
                     f"{r.get('gpu_mib') or 0:.1f} (+{r.get('staging_mib') or 0:.1f}) | {r.get('host_mib') or 0:.0f} | "
                     f"{fmt(r['composite'])} | {fmt(r.get('effect_err'))} | "
                     f"{'beyond its curve' if at is None else f'{at[1]:.0f} spp, {at[0]:.2f} s'} |")
        heat = [r for r in rs if r.get("heatmap")]
        if heat:
            L += ["", f"Error heat-maps of each method's best run ({heat[0]['heatmap_of']} error, full scale "
                  f"{heat[0]['heatmap_max']:.3g} = 3× doing nothing's RMSE):", "",
                  " ".join(f"![{r['method']}]({r['heatmap']})" for r in heat), "",
                  " · ".join(f"{r['method']}: {r['setting']}" for r in heat)]
        L.append("")
    open(os.path.join(DOCS, "benchmark.md"), "w").write("\n".join(L))
    print("wrote docs/benchmark.md", file=sys.stderr)


if not a.from_json and "pareto" not in skip:
    pareto_runs()
report()
common = ["--build", a.build]
for name, script, extra in (("stability", "stability.py", ["--cases", a.cases]),
                            ("shadowmap", "shadowmap_methods.py", ["--cases", a.cases]),
                            ("shadowcases", "shadow_cases.py", ["--cases", a.cases]),
                            ("scaling", "scaling.py", []),
                            ("roofline", "roofline.py", []),
                            ("speed", "speed.py", [])):
    if name in skip:
        continue
    args = [sys.executable, os.path.join(HERE, script)] + (["--from-json"] if a.from_json else common + extra)
    subprocess.run(args, check=True)
