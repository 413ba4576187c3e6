#!/usr/bin/env python3
"""Issue 5's table: every shadow-map method and setting (PCSS taps, CSSM order and prefilter,
VSSM m and H) next to the image-space method isg, on the shared Cycles cases contact and rowdepth
and on isg-synth contact and stack: GPU time per pass group (timestamp queries, best of
--repeat), the method's own GPU memory, RMSE of key.softshadow against ref/softshadow_key.exr
over the reference's mask, and the skipped fraction.

    python3 bench/shadowmap_methods.py [--build build] [--cases ../shared/cases] [--repeat 1]

Writes bench/out/shadowmap_methods.json and docs/benchmark/shadowmap_methods.md."""
import argparse, json, os, platform, re, sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
from common import Tools, compare, run_isg, synth_case

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--cases", default=os.path.join(here, "..", "..", "shared", "cases"))
ap.add_argument("--repeat", type=int, default=1)
ap.add_argument("--synth-size", default="480x270")
ap.add_argument("--from-json", action="store_true")
ap.add_argument("--only", help="re-run only this method's rows (and the synth cases), merging "
                "them into bench/out/shadowmap_methods.json")
a = ap.parse_args()
T = Tools(a.build)
out_json = os.path.join(here, "out", "shadowmap_methods.json")
out_md = os.path.join(here, "..", "docs", "benchmark", "shadowmap_methods.md")

SETTINGS = [
    ("isg", "25 x 49 samples", ["shadows.method=isg"]),
    ("pcss", "16 taps", ["shadows.method=pcss", "shadows.pcss_taps=16"]),
    ("pcss", "32 taps", ["shadows.method=pcss", "shadows.pcss_taps=32"]),
    ("pcss", "64 taps", ["shadows.method=pcss", "shadows.pcss_taps=64"]),
    ("cssm", "M 4, SAT", ["shadows.method=cssm", "shadows.cssm_order=4"]),
    ("cssm", "M 8, SAT", ["shadows.method=cssm", "shadows.cssm_order=8"]),
    ("cssm", "M 16, SAT", ["shadows.method=cssm", "shadows.cssm_order=16"]),
    ("cssm", "M 4, mipmap", ["shadows.method=cssm", "shadows.cssm_order=4", "shadows.cssm_filter=mipmap"]),
    ("cssm", "M 16, mipmap", ["shadows.method=cssm", "shadows.cssm_order=16", "shadows.cssm_filter=mipmap"]),
    ("vssm", "no subdivision (m 1, H 0, VSM leaves)",
     ["shadows.method=vssm", "shadows.vssm_m=1", "shadows.vssm_m_wide=1", "shadows.vssm_h=0",
      "shadows.vssm_leaf_taps=0"]),
    ("vssm", "m 5, H 0", ["shadows.method=vssm", "shadows.vssm_m=5", "shadows.vssm_h=0"]),
    ("vssm", "m 5, H 2 (default)", ["shadows.method=vssm"]),
    ("vssm", "m 5, H 3", ["shadows.method=vssm", "shadows.vssm_h=3"]),
    ("vssm", "m 5, H 4", ["shadows.method=vssm", "shadows.vssm_h=4"]),
]


def group(name):
    """Pass group of a timestamp label: the method's own prefilter passes and the shading."""
    for key, g in (("sat", "SAT build"), ("hsm", "HSM"), ("basis", "basis images"),
                   ("mip", "mipmaps"), ("tiles", "tiles"), ("derive", "derive")):
        if "]." + key in name or "." + key in name.split("]")[-1]:
            return g
    return "shading"


def softshadow_rmse(out, case):
    return compare(T, out, f"{case}/ref/softshadow_key.exr", ["key.softshadow"], "mask")["rmse"]


def run(case, sets):
    r = run_isg(T, case, sets, repeat=a.repeat)
    p = {}
    for k, v in r["passes"].items():
        if k.startswith("shadows."):
            p[group(k)] = p.get(group(k), 0.0) + v
    m = re.search(r"([0-9.]+) MiB of the method's own GPU buffers", r["text"])
    sk = re.search(r"shadows\[key\] \(\w+\): ([0-9.]+)% of", r["text"]) or \
        re.search(r"shadows\[key\]: ([0-9.]+)% of tiles skipped", r["text"])
    return {"passes": p, "mib": float(m.group(1)) if m else 0.0, "skipped": float(sk.group(1)) if sk else None,
            "rmse": softshadow_rmse(r["out"], case)}


def hard_rmse(case):
    """Doing nothing: the input's key.shadow against the reference's key.softshadow."""
    return softshadow_rmse(run_isg(T, case, ["shadows.method=hard"])["out"], case)


if not a.from_json:
    cases = {"shared contact": os.path.join(a.cases, "contact"),
             "shared rowdepth": os.path.join(a.cases, "rowdepth")}
    for s in ("contact", "stack"):
        cases[f"isg-synth {s} {a.synth_size}"] = synth_case(T, s, a.synth_size, 64)
    old = json.load(open(out_json)) if a.only and os.path.exists(out_json) else None
    res = {"machine": platform.node(), "cases": {}}
    for name, case in cases.items():
        r = {"hard": hard_rmse(case), "rows": []}
        for i, (method, label, sets) in enumerate(SETTINGS):
            if old and method != a.only and name in old["cases"]:
                r["rows"].append(old["cases"][name]["rows"][i])
                continue
            x = run(case, sets)
            x.update(method=method, setting=label)
            r["rows"].append(x)
            print(name, method, label, x, flush=True)
        res["cases"][name] = r
    os.makedirs(os.path.dirname(out_json), exist_ok=True)
    json.dump(res, open(out_json, "w"), indent=1)
res = json.load(open(out_json))

L = ["# Shadow-map methods against image-space gathering",
     "",
     "Generated by `python3 bench/shadowmap_methods.py` (run by `python3 bench/bench.py`; lavapipe on this 2-core machine unless "
     "noted). Per case: RMSE of `key.softshadow` against `ref/softshadow_key.exr` over its mask, "
     "the GPU time of the shadow passes by group (timestamp queries), the method's own GPU "
     "buffers, and the share of pixels (isg: of 16x16 tiles) that skipped the filter.",
     ""]
for name, r in res["cases"].items():
    L += [f"## {name}", "", f"Doing nothing (the input's hard `key.shadow`): RMSE {r['hard']:.4f}.", "",
          "| method | setting | RMSE | of doing nothing | GPU ms: prefilter | GPU ms: shading | own GPU MiB | skipped |",
          "|---|---|---|---|---|---|---|---|"]
    for x in r["rows"]:
        p = x["passes"] or {}
        pre = sum(v for k, v in p.items() if k != "shading")
        pre_s = ", ".join(f"{k} {v:.0f}" for k, v in sorted(p.items()) if k != "shading") or "-"
        sk = f"{x['skipped']:.1f}%" if x["skipped"] is not None else "-"
        L.append(f"| {x['method']} | {x['setting']} | {x['rmse']:.4f} | {x['rmse'] / r['hard']:.2f} | "
                 f"{pre:.0f} ({pre_s}) | {p.get('shading', 0):.0f} | {x['mib']:.1f} | {sk} |")
    L.append("")
os.makedirs(os.path.dirname(out_md), exist_ok=True)
open(out_md, "w").write("\n".join(L) + "\n")
print("wrote", out_md)
