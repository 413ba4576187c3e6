#!/usr/bin/env python3
"""Issue 19's table: every shadow method on every Cycles case with a soft-shadow reference, from P
and from Z. Per case, method and input: RMSE of `key.softshadow` against the case's converged Cycles
soft shadow (ref/softshadow_key.exr; a sun case's light is `sun`, its channels and reference named
so) over its mask, and that RMSE as a ratio to doing nothing (the input's hard `key.shadow`, i.e.
shadows.method=hard): below 1 is better than doing nothing.

Inputs: "P" is the case's aovs.exr as it is (world positions from P); "Z" is the same file without
P.X/P.Y/P.Z, so that isg forms positions from the planar depth Z and the scene file's camera.

Cases: every folder with ref/softshadow_<light>.exr under --cases (default ../shared/cases) and under
--own (default $ISG_OWN_CASES, else ../cases-own next to the repository: the repository's own
Cycles cases, rendered by tools/cases/make_cases.sh); a folder that is absent is skipped.

    python3 bench/shadow_cases.py [--build build] [--cases DIR] [--own DIR] [--only a,b]
                                  [--methods isg,pcss,vssm,cssm,auto] [--keep DIR] [--from-json]

--keep DIR keeps every output EXR (DIR/CASE/METHOD-INPUT.exr) and writes an error heat-map
next to it (full scale 3x doing nothing's RMSE), for looking at what breaks.
The own cases contact-far1e5 and contact-far1e6 are the shared contact scene rendered again 1e5 and
1e6 m from the origin. Cycles works in float32 there, so their references are not the origin's
scene (the sphere self-shadows in bumps, edges step by P's float32 step). Per far case the page also
gives each method's error from P over the pixels where Cycles agrees with itself (the masks of both
references, and |far reference - origin reference| < AGREE_TOL), next to the same method's error at
the origin over the same pixels: there the method's own dependence on where the scene stands shows.
That set leaves out most penumbra pixels, where the methods differ. So the page also gives the same
over every pixel of both masks but Cycles' far acne: pixels its origin render lights (input key.shadow
>= LIT, reference >= LIT_REF) that its far render's input shadows (key.shadow < LIT_REF).

Writes bench/out/shadow_cases.json and docs/benchmark/shadow_cases.md."""
import argparse, glob, os, platform, re, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from common import PAGES, SHARED_CASES, Tools, compare, load, run_isg, save, sh

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--cases", default=SHARED_CASES)
ap.add_argument("--own", default=os.environ.get("ISG_OWN_CASES", os.path.join(HERE, "..", "..", "cases-own")))
ap.add_argument("--only", default="", help="comma-separated case names (folder names)")
ap.add_argument("--methods", default="isg,pcss,vssm,cssm,auto")
ap.add_argument("--keep", help="keep outputs and heat-maps under this folder")
ap.add_argument("--set", action="append", default=[], help="a parameter for every run: section.key=value")
ap.add_argument("--from-json", action="store_true", help="rewrite the page from bench/out/shadow_cases.json")
a = ap.parse_args()

INPUTS = ("P", "Z")
ORIGIN = "shared contact"  # the scene the own contact-far* cases move away from the origin
AGREE_TOL = 0.01           # |far reference - origin reference| under this: Cycles agrees with itself
MAP_TOL = 0.01             # metres: the shadow maps' texels further apart than this
LIT = 0.999                # the origin's input key.shadow at least this, its reference at least
LIT_REF = 0.98             # this, and the far input's key.shadow under it: Cycles' far acne


def is_far(label):
    return label.startswith("own contact-far")


def find_cases():
    """(label, folder) of every case with a soft-shadow reference, shared first."""
    out = []
    only = set(filter(None, a.only.split(",")))
    for origin, root in (("shared", a.cases), ("own", a.own)):
        if not os.path.isdir(root):
            print(f"shadow_cases: no {origin} cases at {root}, skipped", file=sys.stderr)
            continue
        for name in sorted(os.listdir(root)):
            d = os.path.join(root, name)
            if light_of(d) and (not only or name in only):
                out.append((f"{origin} {name}", d))
    return out


def light_of(case):
    """The case's light (Cycles cases have one): the name of its ref/softshadow_<name>.exr (`key`,
    or `sun` for a sun case); None where there is none."""
    refs = sorted(glob.glob(os.path.join(case, "ref", "softshadow_*.exr")))
    return os.path.basename(refs[0])[len("softshadow_"):-len(".exr")] if refs else None


def z_only(t, case):
    """The case's AOVs without the position role: isg then forms positions from Z and the camera."""
    dst = os.path.join(t.tmp, os.path.basename(case) + "-z.exr")
    if not os.path.exists(dst):
        info = sh(["oiiotool", "--info", "-v", f"{case}/aovs.exr"])
        chans = [c.strip().rsplit(" (", 1) for c in info.split("channel list:")[1].split("\n")[0].split(",")]
        keep = [(c[0], c[1].rstrip(")") if len(c) > 1 else "float") for c in chans if c[0] not in ("P.X", "P.Y", "P.Z")]
        if len(keep) != len(chans) - 3:
            raise SystemExit(f"{case}/aovs.exr: no P.X/P.Y/P.Z channels to drop")
        types = [arg for n, ty in keep for arg in ("-d", f"{n}={ty}")]  # each channel keeps its pixel type
        sh(["oiiotool", f"{case}/aovs.exr", "--ch", ",".join(n for n, _ in keep), *types, "-o", dst])
    return dst


def measure(t, label, case, methods, outs):
    """Every method from P and from Z; the outputs of ORIGIN and the far cases stay in `outs`."""
    light = light_of(case)
    ref = f"{case}/ref/softshadow_{light}.exr"
    keep = os.path.join(a.keep, os.path.basename(case)) if a.keep else None
    if keep:
        os.makedirs(keep, exist_ok=True)
    res = {"dir": os.path.abspath(case), "rmse": {}, "failed": {}}
    for inp in INPUTS:
        aovs = f"{case}/aovs.exr" if inp == "P" else z_only(t, case)
        for m in ["hard"] + methods:
            key = f"{m}-{inp}"
            out = os.path.join(keep, f"{key}.exr") if keep else None
            if out is None and (label == ORIGIN or is_far(label)):
                out = os.path.join(t.tmp, f"{os.path.basename(case)}-{key}.exr")
            try:
                # From P: P's positions (input.positions=P: refitted where P's float32 step is
                # coarse), but for auto, which keeps every default (input.positions=auto too).
                pos = ["input.positions=P"] if inp == "P" and m != "auto" else []
                r = run_isg(t, case, [f"shadows.method={m}", "reflections.method=none", "dof.method=none"] + pos + a.set,
                            out=out, aovs=aovs)
            except subprocess.CalledProcessError as e:  # a failed run is a result too
                res["failed"][key] = ((e.stderr or "").strip().splitlines() or ["?"])[-1]
                print(label, key, "failed:", res["failed"][key], flush=True)
                continue
            res["device"] = r["device"]
            if m == "auto":  # the method it chose, and why (its printed line)
                c = re.search(rf"^shadows\[{light}\]: (\S+) \(auto: (.*)\)$", r["text"], re.M)
                res.setdefault("auto", {})[inp] = [c.group(1), c.group(2)] if c else ["?", ""]
            hard = res["rmse"].get(f"hard-{inp}")
            heat = os.path.join(keep, f"{key}.png") if keep else None
            e = compare(t, r["out"], ref, [f"{light}.softshadow"], "mask", heatmap=heat,
                        heatmap_max=3 * hard if heat and hard else None)
            res["rmse"][key] = e["rmse"]
            if out:
                outs[(label, key)] = out
            print(label, key, f"rmse {e['rmse']:.5f}" + (f" ratio {e['rmse'] / hard:.2f}" if hard else ""), flush=True)
    return res


def map_agreement(t, far, origin):
    """The far case's key shadow map against the origin's, over the texels where both hold geometry
    (depth under 1e9): mean |difference|, its RMS and the share of texels more than MAP_TOL apart,
    in metres of light distance. Both are Cycles renders of the same scene from the same light,
    so the difference is the renderer's own precision where the scene stands."""
    f_map, o_map = f"{far}/shadowmap_key.exr", f"{origin}/shadowmap_key.exr"
    if not (os.path.exists(f_map) and os.path.exists(o_map)):
        return None
    held = ["--subc", "1e9", "--mulc", "-1", "--clamp:min=0:max=1"]  # 1 where the depth is under 1e9
    both = os.path.join(t.tmp, f"maps-held-{os.path.basename(far)}.exr")
    sh(["oiiotool", f_map, *held, o_map, *held, "--mul", "-d", "float", "-o", both])

    def avg(*args):
        return float(re.search(r"Stats Avg: ([0-9.eE+-]+)", sh(["oiiotool", *args, "--printstats"])).group(1))
    n = avg(both)
    if n <= 0:
        return None
    diff = [f_map, o_map, "--absdiff", both, "--mul"]
    return {"mean_abs": avg(*diff) / n,
            "rms": (avg(*diff, "--dup", "--mul") / n) ** 0.5,
            "over_tol": avg(f_map, o_map, "--absdiff", "--subc", f"{MAP_TOL}", "--mulc", "1e9",
                            "--clamp:min=0:max=1", both, "--mul") / n}


def far_agreement(t, res, outs, methods):
    """Per far case: the references' RMSE to each other, and every method's RMSE from P over the
    pixels where they agree, at the far case and at the origin."""
    cases = res["cases"]
    if ORIGIN not in cases:
        return {}
    o_ref = f"{cases[ORIGIN]['dir']}/ref/softshadow_key.exr"
    out = {}
    for label, r in cases.items():
        if not is_far(label):
            continue
        f_ref = f"{r['dir']}/ref/softshadow_key.exr"
        agree = os.path.join(t.tmp, f"agree-{os.path.basename(r['dir'])}.exr")
        sh(["oiiotool", f_ref, "--ch", "key.softshadow", o_ref, "--ch", "key.softshadow", "--absdiff",
            "--subc", f"{AGREE_TOL}", "--mulc", "-1e9", "--clamp:min=0:max=1", f_ref, "--ch", "mask", "--mul",
            o_ref, "--ch", "mask", "--mul", "--chnames", "A", "-d", "float", "-o", agree])
        cover = float(re.search(r"Stats Avg: ([0-9.eE+-]+)", sh(["oiiotool", agree, "--printstats"])).group(1))
        mask = float(re.search(r"Stats Avg: ([0-9.eE+-]+)",
                               sh(["oiiotool", f_ref, "--ch", "mask", "--printstats"])).group(1))
        # Cycles' self-shadowing at the far case (acne): pixels its origin render lights, in the
        # input's ray-traced key.shadow (>= LIT) and in the reference (>= LIT_REF), that its far
        # render's input shadows (key.shadow < LIT_REF). The rest of both masks: "clean".
        at_least = lambda v: ["--subc", f"{v}", "--mulc", "1e9", "--addc", "1", "--clamp:min=0:max=1"]
        o_aovs, f_aovs = f"{cases[ORIGIN]['dir']}/aovs.exr", f"{r['dir']}/aovs.exr"
        clean = os.path.join(t.tmp, f"clean-{os.path.basename(r['dir'])}.exr")
        sh(["oiiotool", o_aovs, "--ch", "key.shadow", *at_least(LIT), o_ref, "--ch", "key.softshadow",
            *at_least(LIT_REF), "--mul", f_aovs, "--ch", "key.shadow", *at_least(LIT_REF), "--mulc", "-1", "--addc",
            "1", "--mul", "--mulc", "-1", "--addc", "1", f_ref, "--ch", "mask", "--mul", o_ref, "--ch", "mask",
            "--mul", "--chnames", "A", "-d", "float", "-o", clean])
        kept = float(re.search(r"Stats Avg: ([0-9.eE+-]+)", sh(["oiiotool", clean, "--printstats"])).group(1))
        a = {"refs_rmse": compare(t, f_ref, o_ref, ["key.softshadow"], "mask")["rmse"],
             "agree_share": cover / mask if mask > 0 else 0.0, "rmse": {},
             "clean_share": kept / mask if mask > 0 else 0.0, "clean": {},
             "map": map_agreement(t, r["dir"], cases[ORIGIN]["dir"])}
        for m in ["hard"] + methods:
            k = f"{m}-P"
            if (label, k) in outs and (ORIGIN, k) in outs:  # from P
                a["rmse"][m] = [compare(t, outs[(label, k)], f_ref, ["key.softshadow"], f"{agree}:A")["rmse"],
                                compare(t, outs[(ORIGIN, k)], o_ref, ["key.softshadow"], f"{agree}:A")["rmse"]]
        for inp in INPUTS:  # from P and from Z ("hard" is the same input either way)
            for m in ["hard"] + methods:
                k = f"{m}-{inp}"
                if (label, k) in outs and (ORIGIN, k) in outs:
                    a["clean"][k] = [compare(t, outs[(label, k)], f_ref, ["key.softshadow"], f"{clean}:A")["rmse"],
                                     compare(t, outs[(ORIGIN, k)], o_ref, ["key.softshadow"], f"{clean}:A")["rmse"]]
        out[label] = a
        print(label, "agreement", a, flush=True)
    return out


def ratio(r, m, inp):
    v, h = r["rmse"].get(f"{m}-{inp}"), r["rmse"].get(f"hard-{inp}")
    return None if v is None or not h else v / h


def cell(r, m, inp):
    if f"{m}-{inp}" in r["failed"]:
        return "failed"
    x = ratio(r, m, inp)
    if x is None:
        return "-"
    s = f"{x:.2f}"
    return f"**{s}**" if x >= 1 else s


def report(res):
    cases = res["cases"]
    names = list(cases)
    methods = res["methods"]
    L = ["# Shadow methods on Cycles cases: far from the origin, large low lights, grazing receivers", "",
         "Generated by `python3 bench/shadow_cases.py` (issue 19). Every case here is a Blender Cycles render with "
         "a converged soft-shadow reference: the shared cases (`../shared/cases`) and the repository's own "
         "(`tools/cases/`, rendered outside the repository; see tools/cases/README.md). Number: RMSE of "
         "`key.softshadow` against the reference's `key.softshadow` over its `mask`, divided by the RMSE of doing "
         "nothing (the input's hard `key.shadow`); below 1 is better than doing nothing, **bold** is not. "
         "P: positions from the P channels (`input.positions=P`; refitted into a planar depth where P's float32 "
         "step is wider than a 16th of a pixel at a scene radius from the camera, here at 1e5 and 1e6 m from the "
         "origin); Z: the "
         "same AOVs without P, positions formed from Z and the camera. auto P keeps every default, "
         "`input.positions=auto` too (P where the input has it). "
         "Default settings of every method; reflections and depth of field off.", "",
         f"Machine: {res['machine']}; device: {res.get('device', '?')}.", "",
         "| case | hard RMSE | " + " | ".join(f"{m} P | {m} Z" for m in methods) + " |",
         "|---|---|" + "---|---|" * len(methods)]
    for n in names:
        r = cases[n]
        h = f"{r['rmse']['hard-P']:.4f}" if "hard-P" in r["rmse"] else "-"
        L.append(f"| {n} | {h} | " + " | ".join(f"{cell(r, m, 'P')} | {cell(r, m, 'Z')}" for m in methods) + " |")
    L += ["", "The RMSEs themselves:", "",
          "| case | hard | " + " | ".join(f"{m} P | {m} Z" for m in methods) + " |",
          "|---|---|" + "---|---|" * len(methods)]
    for n in names:
        r = cases[n]
        f = lambda k: "failed" if k in r["failed"] else (f"{r['rmse'][k]:.4f}" if k in r["rmse"] else "-")
        L.append(f"| {n} | {f('hard-P')} | " + " | ".join(f"{f(m + '-P')} | {f(m + '-Z')}" for m in methods) + " |")
    if "auto" in methods:
        L += ["", "`shadows.method=auto`'s choice on each case (what `isg run` prints), from P / from Z:", ""]
        for n in names:
            ch = cases[n].get("auto", {})
            L.append(f"- {n}: " + " / ".join(f"**{ch[i][0]}** ({ch[i][1]})" if i in ch else "-" for i in INPUTS))
    far = res.get("far_agreement", {})
    if far:
        L += ["", "## Far from the origin: where Cycles agrees with itself", "",
              f"The far cases' references against the origin's ({ORIGIN}) over the mask, and each method's RMSE "
              f"from P over the pixels where the two references differ by under {AGREE_TOL} (and both masks "
              "hold): at the far case / at the origin, and the change. Doing nothing's RMSE over the whole mask "
              "is about 0.0435 on all three. The references' RMSE to each other is what the origin's reference "
              "itself, the scene's soft shadow where Cycles computes it exactly, scores against the far one; "
              "in brackets as a ratio to doing nothing's there, the first table's unit.", "",
              "| case | references' RMSE to each other | pixels of the mask where they agree | " +
              " | ".join(["hard"] + methods) + " |", "|---|---|---|" + "---|" * (len(methods) + 1)]
        for n, fa in far.items():
            hard_far = cases[n]["rmse"].get("hard-P")
            cells = []
            for m in ["hard"] + methods:
                v = fa["rmse"].get(m)
                cells.append("-" if not v else f"{v[0]:.5f} / {v[1]:.5f} ({100 * (v[0] / v[1] - 1):+.0f} %)")
            as_output = f" ({fa['refs_rmse'] / hard_far:.2f})" if hard_far else ""
            L.append(f"| {n} | {fa['refs_rmse']:.4f}{as_output} | {100 * fa['agree_share']:.0f} % | " + " | ".join(cells) + " |")
        clean = {n: fa for n, fa in far.items() if fa.get("clean")}
        if clean:
            L += ["", f"The same, over the pixels of both masks but those where Cycles' far render self-shadows "
                  f"(acne): its origin render lights the pixel (the input's ray-traced `key.shadow` at least {LIT}, "
                  f"the reference at least {LIT_REF}) and its far render's input shadows it (`key.shadow` under "
                  f"{LIT_REF}). There every method keeps the input's ray-traced `key.shadow`, the far render's "
                  "acne, which its reference has in other places. Per method and input: RMSE at the far case / "
                  "at the origin, the change, and the ratio to doing nothing at each.", "",
                  "| case | input | pixels of the mask kept | " + " | ".join(["hard"] + methods) + " |",
                  "|---|---|---|" + "---|" * (len(methods) + 1)]
            for n, fa in clean.items():
                for inp in INPUTS:
                    h = fa["clean"].get(f"hard-{inp}")
                    cells = []
                    for m in ["hard"] + methods:
                        v = fa["clean"].get(f"{m}-{inp}")
                        if not v:
                            cells.append("-")
                            continue
                        c = f"{v[0]:.5f} / {v[1]:.5f} ({100 * (v[0] / v[1] - 1):+.0f} %)"
                        if m != "hard" and h and h[0] > 0 and h[1] > 0:
                            c += f"; {v[0] / h[0]:.2f} / {v[1] / h[1]:.2f}"
                        cells.append(c)
                    L.append(f"| {n} | {inp} | {100 * fa['clean_share']:.1f} % | " + " | ".join(cells) + " |")
        maps = {n: fa["map"] for n, fa in far.items() if fa.get("map")}
        if maps:
            L += ["", "The same scene's key shadow map as Cycles renders it there, against the origin's (texels "
                  "where both hold geometry; distances from the light in mm). The shadow-map methods filter that "
                  "map and inherit its error, the renderer's own; `shadows.input_edges` keeps the input's "
                  "ray-traced edge where the penumbra is narrow.", "",
                  f"| case | mean abs difference | RMS difference | texels more than {1000 * MAP_TOL:.0f} mm apart |",
                  "|---|---|---|---|"]
            for n, mp in maps.items():
                L.append(f"| {n} | {1000 * mp['mean_abs']:.1f} | {1000 * mp['rms']:.1f} | {100 * mp['over_tol']:.1f} % |")
    fails = [(n, k, msg) for n in names for k, msg in cases[n]["failed"].items()]
    if fails:
        L += ["", "Failed runs (isg's one-line error):", ""] + [f"- {n}, {k}: `{msg}`" for n, k, msg in fails]
    repo = os.path.dirname(HERE)
    L += ["", "Cases (relative to the repository): " +
          "; ".join(f"{n}: `{os.path.relpath(cases[n]['dir'], repo)}`" for n in names) + ".", ""]
    os.makedirs(PAGES, exist_ok=True)
    open(os.path.join(PAGES, "shadow_cases.md"), "w").write("\n".join(L))
    print("wrote docs/benchmark/shadow_cases.md")


if not a.from_json:
    t = Tools(a.build)
    methods = [m for m in a.methods.split(",") if m]
    found = find_cases()
    if not found:
        raise SystemExit("shadow_cases: no case with ref/softshadow_<light>.exr found")
    res = {"machine": platform.node(), "methods": methods, "cases": {}}
    outs = {}
    for label, d in found:
        res["cases"][label] = measure(t, label, d, methods, outs)
    res["far_agreement"] = far_agreement(t, res, outs, methods)
    res["device"] = next((c.get("device") for c in res["cases"].values() if c.get("device")), "?")
    save("shadow_cases.json", res)
report(load("shadow_cases.json"))
