#!/usr/bin/env python3
"""First cut of issue 9's benchmark: every effect x method x sample setting on the shared
Cycles cases, GPU time per pass (timestamp queries, best of --repeat) and error against the
case's reference over its mask, next to Cycles' own time-to-error curve (ref/drt/timings.json).
Writes bench/out/runs.json and docs/benchmark.md.

    python3 bench/bench.py [--build build] [--cases ../shared/cases] [--repeat 3]

Not yet here (issue 9 stays open): plots, isg-synth cases, scaling sweeps, the numerical
stability table, memory, the CSSM/VSSM rows."""
import argparse, json, os, platform, re, subprocess, sys, tempfile, time

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--cases", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared", "cases"))
ap.add_argument("--repeat", type=int, default=3)
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
json.dump(rows, open(os.path.join(os.path.dirname(__file__), "out", "runs.json"), "w"), indent=1)

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
     "First cut of issue 9: plots, isg-synth cases, scaling, stability and memory are still to come.", ""]
for c in ("contact", "rowdepth", "gloss", "dof"):
    rs = [r for r in rows if r["case"] == c]
    if not rs:
        continue
    curve = cycles(os.path.join(a.cases, c))
    L += [f"## {c}", "", "Cycles: " + ", ".join(f"{s} spp {t:.2f} s → {e:.5f}" for s, t, e in curve), "",
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
