"""What every benchmark script shares: running `isg run --timings` and parsing it, `isg compare`,
isg-synth cases generated on the fly, the device's name. Imported by bench/*.py."""
import json, os, re, subprocess, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "out")               # raw results (ignored by git)
DOCS = os.path.join(HERE, "..", "docs")       # the pages
PAGES = os.path.join(DOCS, "benchmark")       # companion pages, plots, heat-maps
SHARED_CASES = os.path.join(HERE, "..", "..", "shared", "cases")


class Tools:
    def __init__(self, build):
        self.isg = os.path.join(build, "cli", "isg")
        self.synth = os.path.join(build, "tools", "synth", "isg-synth")
        self.tmp = tempfile.mkdtemp(prefix="isg-bench-")


def sh(args):
    return subprocess.run(args, check=True, capture_output=True, text=True).stdout


def parse_timings(text):
    """`isg run --timings` output: GPU ms per pass (with "total"), the measured memory peaks,
    the device."""
    passes = {m.group(1): float(m.group(2)) for m in re.finditer(r"^\s+(\S+)\s+([0-9.]+) ms$", text, re.M)}
    r = {"passes": passes, "gpu_total_ms": passes.pop("total", sum(passes.values()))}
    m = re.search(r"memory peak: GPU ([0-9.]+) MiB device-local \+ ([0-9.]+) MiB staging.*host ([0-9.]+) MiB", text)
    if m:
        r.update(gpu_mib=float(m.group(1)), staging_mib=float(m.group(2)), host_mib=float(m.group(3)))
    m = re.search(r"^device: (.*)$", text, re.M)
    r["device"] = m.group(1) if m else "?"
    r["text"] = text
    return r


def run_isg(t, case, sets, out=None, repeat=1, aovs=None):
    """`isg run` on a case folder (aovs.exr, scene.json), best GPU time per pass over `repeat`
    runs, mean wall time; returns the parsed timings plus "out" (the written EXR)."""
    out = out or os.path.join(t.tmp, "o.exr")
    cmd = [t.isg, "run", aovs or f"{case}/aovs.exr", "--scene", f"{case}/scene.json", "-o", out, "--timings"]
    for s in sets:
        cmd += ["--set", s]
    best, wall = None, 0.0
    for _ in range(repeat):
        t0 = time.time()
        r = parse_timings(sh(cmd))
        wall += time.time() - t0
        if best is not None:
            r["passes"] = {k: min(v, best["passes"].get(k, v)) for k, v in r["passes"].items()}
            r["gpu_total_ms"] = min(r["gpu_total_ms"], best["gpu_total_ms"])
        best = r
    best["wall_s"] = wall / repeat
    best["out"] = out
    return best


def compare(t, out, ref, channels, mask=None, heatmap=None, heatmap_max=None):
    """`isg compare --json` over `mask` ("CHANNEL" or "FILE:CHANNEL"): rmse, psnr, ssim, max_abs."""
    cmd = [t.isg, "compare", out, ref, "--json", "--channels", *channels]
    if mask:
        cmd += ["--mask", mask]
    if heatmap:
        cmd += ["--heatmap", heatmap]
        if heatmap_max:
            cmd += ["--heatmap-max", f"{heatmap_max:g}"]
    a = json.loads(sh(cmd))["all"]
    return {k: a[k] for k in ("rmse", "psnr", "ssim", "max_abs")}


def synth_case(t, scene, size, spp=64, extra=(), name=None):
    """An isg-synth case in the temporary folder (`size` "WxH")."""
    w, h = size.split("x")
    d = os.path.join(t.tmp, name or f"{scene}-{size}-{spp}")
    if not os.path.isdir(d):
        sh([t.synth, scene, "--out", d, "--width", w, "--height", h, "--ref-spp", str(spp), *extra])
    return d


def exr_attribute(path, name):
    """A header attribute, via oiiotool (None if absent)."""
    m = re.search(rf'^\s+{re.escape(name)}: "?([^"\n]*)"?$', sh(["oiiotool", "--info", "-v", path]), re.M)
    return m.group(1) if m else None


def load(name):
    return json.load(open(os.path.join(OUT, name)))


def save(name, data):
    os.makedirs(OUT, exist_ok=True)
    json.dump(data, open(os.path.join(OUT, name), "w"), indent=1)
