#!/usr/bin/env python3
"""Blender's compositor Defocus node next to isg on the shared `dof` case, error and time in one
run (-> docs/benchmark/dof_blender.md, raw numbers in bench/out/dof_blender.json):

    python3 bench/blender_defocus.py [--build build] [--case ../shared/cases/dof] [--repeat 3]
                                     [--blender blender] [--quiet-load 1.0] [--quiet-wait 1200]
                                     [--from-json]

Blender runs headless (`blender -b --factory-startup --python <script> -- <json>`) on a
compositor tree: Image (cycles_native.exr, layer ViewLayer: Combined and Depth) -> Defocus
(use_zbuffer, Z = Depth, circular bokeh, angle 0, no preview, no gamma correction, threshold at
its default, the scene camera set up from scene.json: focal length, sensor width, horizontal fit,
focus distance) -> Composite, written as a float RGBA OpenEXR at the image's size, 100 %.
No Render Layers node, so Blender renders nothing: the render is the compositor alone.

Blender's Defocus is run twice: with scene.json's f-stop as it stands ("default": Blender's own
scaling) and with the f-stop that makes its circle of confusion the case's thin lens ("matched",
see lens() below). Each Blender timing is taken on the same tree with the Defocus node muted
(Image -> Composite only, same load and write) and reported as the difference: the Defocus
node's own cost. isg runs on aovs.exr (the same render in the contract's names) with
dof.method=none / layered / isg. Every error is RGB RMSE against ref/beauty.exr over every pixel,
as bench/bench.py scores the dof case; next to it, the same with both images clamped at 1
(ref/drt/timings.json's `_clamp1`). Every time is the best of --repeat runs, taken once the
machine is quiet (1-minute load average under --quiet-load, waited for up to --quiet-wait s).

Where `blender` is absent the script says so, writes the page saying so and exits 0."""
import argparse, json, math, os, platform, re, resource, shutil, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import OUT, PAGES, SHARED_CASES, Tools, compare, parse_timings, save, sh

PAGE = os.path.join(PAGES, "dof_blender.md")
JSON = "dof_blender.json"

# The Blender side: builds the tree, runs the compositor, prints one result line.
INNER = r'''
import bpy, json, sys, time
p = json.loads(sys.argv[sys.argv.index("--") + 1])
sc = bpy.context.scene
for ob in list(bpy.data.objects):
    bpy.data.objects.remove(ob)
cam = bpy.data.cameras.new("isg_camera")
cam.lens = p["focal_length_mm"]
cam.sensor_width = p["sensor_width_mm"]
cam.sensor_fit = "HORIZONTAL"
cam.dof.use_dof = True
cam.dof.focus_distance = p["focus_distance"]
cam.dof.aperture_fstop = p["fstop"]
cam.clip_start, cam.clip_end = p["near"], p["far"]
ob = bpy.data.objects.new("isg_camera", cam)
sc.collection.objects.link(ob)
sc.camera = ob

r = sc.render
r.resolution_x, r.resolution_y, r.resolution_percentage = p["width"], p["height"], 100
r.pixel_aspect_x = r.pixel_aspect_y = 1.0
r.use_compositing, r.use_sequencer = True, False
r.image_settings.file_format = "OPEN_EXR"
r.image_settings.color_mode = "RGBA"
r.image_settings.color_depth = "32"
r.image_settings.exr_codec = "ZIP"
r.filepath = p["out"]
r.use_file_extension = False
sc.view_settings.view_transform = "Standard"   # EXR output is linear anyway; be explicit
sc.view_settings.look = "None"
sc.view_settings.exposure, sc.view_settings.gamma = 0.0, 1.0

sc.use_nodes = True
t = sc.node_tree
t.execution_mode = p["execution_mode"]
for n in list(t.nodes):
    t.nodes.remove(n)
img = bpy.data.images.load(p["exr"])
src = t.nodes.new("CompositorNodeImage")
src.image = img
src.layer = "ViewLayer"
d = t.nodes.new("CompositorNodeDefocus")
d.bokeh = "CIRCLE"
d.angle = 0.0
d.use_gamma_correction = False
d.f_stop = p["f_stop"]
d.blur_max = p["blur_max"]
d.threshold = p["threshold"]
d.use_preview = False
d.use_zbuffer = True
d.z_scale = 1.0
d.scene = sc
out = t.nodes.new("CompositorNodeComposite")
out.use_alpha = True
t.links.new(src.outputs["Combined"], d.inputs["Image"])
t.links.new(src.outputs["Depth"], d.inputs["Z"])
t.links.new(d.outputs["Image"], out.inputs["Image"])
d.mute = p["mute"]   # muted: Image passes straight through, the rest of the run identical

t0 = time.perf_counter()
bpy.ops.render.render(write_still=True)
secs = time.perf_counter() - t0
node = {k: getattr(d, k) for k in ("bokeh", "angle", "f_stop", "blur_max", "threshold", "use_preview",
                                   "use_zbuffer", "z_scale", "use_gamma_correction", "mute")}
print("ISG_BLENDER " + json.dumps({"render_s": secs, "node": node, "execution_mode": t.execution_mode,
                                   "render_quality": t.render_quality, "threads": r.threads,
                                   "version": bpy.app.version_string, "camera": {
                                       "lens": cam.lens, "sensor_width": cam.sensor_width,
                                       "sensor_fit": cam.sensor_fit,
                                       "focus_distance": cam.dof.focus_distance}}), flush=True)
'''


def lens(cam, z_min):
    """The case's circle of confusion and Blender's, both as radii in pixels, per dioptre.

    Cycles' thin lens (what ref/beauty.exr was rendered with) keeps the pinhole's field of view and
    bends each ray through the focal plane: a point at depth z lands R·(1/z_f − 1/z) off in
    tangent units, R = f / (2 N) the aperture radius, i.e.
        r_px = k_case · |1/z_f − 1/z|,  k_case = f² / (2 N) · W / sensor      (f, sensor in m).
    Blender's Defocus (COM_ConvertDepthToRadiusOperation, 3.4) computes
        r = ½ · |a · (s · (1/z_f − 1/z) − 1)|,  a = ½ · lens / (aspect · sensor) / N,
        s = min(W, H) · 2 · lens / sensor      (lens, sensor in mm; aspect = min/max side),
    i.e. r ≈ k_blender · |1/z_f − 1/z| with k_blender = lens² · W / (2 N sensor²): the
    millimetres are never turned into scene units, so k_blender / k_case = 1000 / sensor_mm
    (27.8 on a 36 mm sensor), whatever the lens. The f-stop that matches is N · 1000 / sensor_mm;
    the "− 1" adds ½·a pixel everywhere (0.03 px at the matched f-stop)."""
    f, s, N, W, H = cam["focal_length_mm"], cam["sensor_width_mm"], cam["fstop"], cam["width"], cam["height"]
    zf = cam["focus_distance"]
    k_case = (f / 1000) ** 2 / (2 * N) * W / (s / 1000)
    k_isg = k_case * zf * 1000 / (zf * 1000 - f)      # isg's eq. 15 keeps the focusing lens's z_f/(z_f − f)
    k_blender = f * f * W / (2 * N * s * s)
    r_max = k_case * abs(1 / zf - 1 / z_min)
    r_inf = k_case / zf
    return {"k_case": k_case, "k_isg": k_isg, "k_blender": k_blender, "ratio": k_blender / k_case,
            "fstop_matched": N * k_blender / k_case, "r_max_px": r_max, "r_inf_px": r_inf,
            "r_max_blender_default_px": k_blender * abs(1 / zf - 1 / z_min),
            "blur_max": float(math.ceil(r_max) + 1), "z_min": z_min}


def loadavg():
    return float(open("/proc/loadavg").read().split()[0])


def wait_quiet(limit, wait):
    """Wait (every 30 s) until the 1-minute load average is under `limit`; False if it never was."""
    t0 = time.time()
    while True:
        la = loadavg()
        if la < limit:
            return True, la, time.time() - t0
        if time.time() - t0 >= wait:
            return False, la, time.time() - t0
        print(f"load average {la:.2f} >= {limit}: waiting", file=sys.stderr, flush=True)
        time.sleep(30)


def timed(cmd):
    """Run cmd; (CompletedProcess, wall s, CPU s = the child's user + system time)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return p, wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def blender_run(blender, inner, params, repeat):
    """Best of `repeat` Blender processes: whole-process wall time and the render call's own time."""
    best = None
    for _ in range(repeat):
        p, wall, cpu = timed([blender, "-b", "--factory-startup", "--python", inner, "--", json.dumps(params)])
        m = re.search(r"^ISG_BLENDER (.*)$", p.stdout, re.M)
        if p.returncode != 0 or not m or not os.path.exists(params["out"]):
            sys.exit(f"blender failed (rc {p.returncode}):\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}")
        r = json.loads(m.group(1))
        r["wall_s"], r["cpu_s"] = wall, cpu
        if best is None:
            best = r
        else:
            for k in ("wall_s", "cpu_s", "render_s"):
                best[k] = min(best[k], r[k])
    return best


def isg_run(t, case, sets, out, repeat):
    """Best of `repeat` `isg run --timings`: wall time and GPU time (dof passes, all passes)."""
    cmd = [t.isg, "run", f"{case}/aovs.exr", "--scene", f"{case}/scene.json", "-o", out, "--timings"]
    for s in sets:
        cmd += ["--set", s]
    best = None
    for _ in range(repeat):
        p, wall, cpu = timed(cmd)
        if p.returncode != 0:
            sys.exit(f"isg failed (rc {p.returncode}): {' '.join(cmd)}\n{p.stderr[-3000:]}")
        r = parse_timings(p.stdout)
        r["wall_s"], r["cpu_s"] = wall, cpu
        r["dof_ms"] = sum(v for k, v in r["passes"].items() if k.startswith("dof."))
        if best is None:
            best = r
        else:
            for k in ("wall_s", "cpu_s", "dof_ms", "gpu_total_ms"):
                best[k] = min(best[k], r[k])
    best.pop("text", None)
    best["cmd"] = " ".join("OUT.exr" if c == out else os.path.relpath(c) if c.startswith("/") else c for c in cmd)
    return best


def errors(t, tmp, out, ref):
    """RGB RMSE against ref over every pixel, plain and with both images clamped at 1."""
    plain = compare(t, out, ref, ["R", "G", "B"])
    a, b = os.path.join(tmp, "a1.exr"), os.path.join(tmp, "b1.exr")
    sh(["oiiotool", out, "--ch", "R,G,B", "--clamp:max=1", "-d", "float", "-o", a])
    sh(["oiiotool", ref, "--ch", "R,G,B", "--clamp:max=1", "-d", "float", "-o", b])
    return {"rmse": plain["rmse"], "psnr": plain["psnr"], "ssim": plain["ssim"], "max_abs": plain["max_abs"],
            "rmse_clamp1": compare(t, a, b, ["R", "G", "B"])["rmse"]}


def z_min(exr):
    """The nearest depth in the AOVs (oiiotool's stats of Z)."""
    m = re.search(r"Stats Min: ([0-9.eE+-]+)", sh(["oiiotool", exr, "--ch", "Z", "--printstats"]))
    return float(m.group(1))


def machine():
    cpu = "?"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    return f"{platform.system()} {platform.release()}, {cpu}, {os.cpu_count()} cores"


def measure(a):
    t = Tools(a.build)
    case = os.path.abspath(a.case)
    cam = dict(json.load(open(f"{case}/scene.json"))["camera"])
    L = lens(cam, z_min(f"{case}/aovs.exr"))
    tmp = tempfile.mkdtemp(prefix="isg-blender-")
    inner = os.path.join(tmp, "defocus_tree.py")
    open(inner, "w").write(INNER)
    ref = f"{case}/ref/beauty.exr"
    base = {k: cam[k] for k in ("focal_length_mm", "sensor_width_mm", "focus_distance", "fstop", "near", "far",
                                "width", "height")}
    base.update(exr=f"{case}/cycles_native.exr", threshold=1.0, execution_mode=a.execution_mode)

    quiet, la, waited = wait_quiet(a.quiet_load, a.quiet_wait)
    print(f"load average {la:.2f} ({'quiet' if quiet else 'NOT quiet'} after {waited:.0f} s)", file=sys.stderr)
    load_before = la

    bl = {}
    # Blender: the same tree muted, then Defocus at the case's f-stop and at the matched one.
    for name, fstop in (("muted", cam["fstop"]), ("default", cam["fstop"]), ("matched", L["fstop_matched"])):
        out = os.path.join(tmp, f"blender-{name}.exr")
        p = dict(base, f_stop=fstop, blur_max=L["blur_max"], mute=(name == "muted"), out=out)
        r = blender_run(a.blender, inner, p, a.repeat)
        r["err"] = errors(t, tmp, out, ref)
        bl[name] = r
        print(f"blender {name}: f/{fstop:.3f} wall {r['wall_s']:.2f} s, render {r['render_s']:.3f} s, "
              f"RMSE {r['err']['rmse']:.5f}", file=sys.stderr, flush=True)
    bl["command"] = f"{a.blender} -b --factory-startup --python defocus_tree.py -- '<json>'"
    bl["params_example"] = dict(base, exr=os.path.relpath(base["exr"]), f_stop=L["fstop_matched"],
                                blur_max=L["blur_max"], mute=False, out="OUT.exr")

    isg = {}
    for name, sets in (("none", ["dof.method=none"]), ("layered", ["dof.method=layered"]),
                       ("isg", ["dof.method=isg"]), ("layered 256", ["dof.method=layered", "dof.samples=256"]),
                       ("isg 256", ["dof.method=isg", "dof.samples=256"])):
        out = os.path.join(tmp, f"isg-{name.replace(' ', '-')}.exr")
        r = isg_run(t, case, sets, out, a.repeat)
        r["err"] = errors(t, tmp, out, ref)
        isg[name] = r
        print(f"isg {name}: wall {r['wall_s']:.2f} s, GPU dof {r['dof_ms']:.1f} ms, RMSE {r['err']['rmse']:.5f}",
              file=sys.stderr, flush=True)
    load_after = loadavg()   # the timed runs end here

    # Errors only (one run each): the f-stop around the matched one, and scene.json's f-stop with a
    # larger max blur (the default row's error is set by max blur, not by the f-stop).
    sweep = []
    for fstop, blur in ([(L["fstop_matched"] * m, L["blur_max"]) for m in (0.5, 0.75, 0.9, 1.1, 1.33, 2.0)]
                        + [(cam["fstop"], 32.0), (cam["fstop"], 64.0)]):
        out = os.path.join(tmp, "blender-sweep.exr")
        r = blender_run(a.blender, inner, dict(base, f_stop=fstop, blur_max=blur, mute=False, out=out), 1)
        sweep.append({"f_stop": fstop, "blur_max": blur, "render_s": r["render_s"], "err": errors(t, tmp, out, ref)})
        print(f"blender sweep f/{fstop:.2f} max blur {blur:g}: RMSE {sweep[-1]['err']['rmse']:.5f}",
              file=sys.stderr, flush=True)
    bl["sweep"] = sweep
    return {"machine": machine(), "case": os.path.relpath(case), "lens": L, "size": f"{cam['width']}×{cam['height']}",
            "blender": bl, "isg": isg,
            "quiet": quiet, "load_before": load_before, "load_after": load_after, "repeat": a.repeat,
            "when": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "commit": subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                     text=True).stdout.strip()}


def page(d, skipped=None):
    L = []
    w = L.append
    w("# Blender's Defocus node next to isg (shared `dof` case)\n")
    w("Generated by `python3 bench/blender_defocus.py` (raw numbers in bench/out/dof_blender.json). "
      "The anchor to beat: Blender's compositor Defocus node, fed the same render's Combined and Depth "
      "(`cycles_native.exr`) and the camera of scene.json, scored like isg's dof rows on "
      "[the benchmark page](../benchmark.md#shared-dof).\n")
    if skipped:
        w(f"**Not measured on this machine: {skipped}** Install Blender (Debian 12: `apt-get install "
          "blender`, 3.4.1) and run the command again.\n")
        if not d:
            return "\n".join(L)
        w("The figures below are the last ones measured (bench/out/dof_blender.json).\n")
    Ln, bl, isg = d["lens"], d["blender"], d["isg"]
    nothing = isg["none"]["err"]
    w(f"Measured {d['when']} at commit {d['commit']}. Machine: {d['machine']}; isg's device: "
      f"{isg['layered']['device']}; Blender {bl['matched']['version']} (`blender -b --factory-startup`, "
      f"CPU compositor, execution mode {bl['matched']['execution_mode']}, {bl['matched']['threads']} threads). "
      f"Every time is the best of {d['repeat']} runs; load average {d['load_before']:.2f} before the runs "
      f"({'quiet' if d['quiet'] else 'the machine never got quiet: the times are on a busy machine'}), "
      f"{d['load_after']:.2f} after.\n")
    w("- **error**: RGB RMSE against ref/beauty.exr over every pixel (the mask bench.py uses for this case); "
      "*clamped*: both images clamped at 1 first, so the 8 bright emitters (up to 40) do not dominate. "
      "*of nothing*: the RMSE over doing nothing's (the pinhole beauty, isg's `dof.method=none`).")
    w("- **Blender**: *Defocus s* = the render call (compositor only: no Render Layers node, nothing is "
      "rendered) minus the same call with the Defocus node muted, i.e. the node's own cost; *wall* = the "
      "whole `blender` process (start-up, EXR read, compositor, EXR write).")
    w("- **isg**: *GPU ms* = the dof passes' timestamp-query time (all passes in brackets); *wall* = the "
      "whole `isg run` process (read, device start-up, upload, GPU, write).")
    w("- *CPU s*: the whole process's user + system time (every thread), less sensitive than wall time to "
      "other work on the machine; for Blender's Defocus rows, in brackets, minus the muted tree's: the "
      "node's own CPU time.\n")
    w("| method | setting | RMSE | of nothing | RMSE clamped | of nothing | Defocus s / GPU ms (all) | wall s | CPU s |")
    w("|---|---|---|---|---|---|---|---|---|")
    cpu = lambda r: f"{r['cpu_s']:.2f}" if "cpu_s" in r else "-"
    mu = bl["muted"]
    w(f"| doing nothing (pinhole beauty) | isg dof.method=none | {nothing['rmse']:.5f} | 1.00 | "
      f"{nothing['rmse_clamp1']:.5f} | 1.00 | - | {isg['none']['wall_s']:.2f} | {cpu(isg['none'])} |")
    w(f"| Blender, Defocus muted | same tree, node muted | {mu['err']['rmse']:.5f} | "
      f"{mu['err']['rmse'] / nothing['rmse']:.2f} | {mu['err']['rmse_clamp1']:.5f} | "
      f"{mu['err']['rmse_clamp1'] / nothing['rmse_clamp1']:.2f} | (render call {mu['render_s']:.3f} s) | "
      f"{mu['wall_s']:.2f} | {cpu(mu)} |")
    for name, label in (("default", f"f/{bl['default']['node']['f_stop']:g} (scene.json's, Blender's scaling)"),
                        ("matched", f"f/{bl['matched']['node']['f_stop']:.2f} (matched to the case's lens)")):
        r = bl[name]
        w(f"| **Blender Defocus** | {label}, max blur {r['node']['blur_max']:g} | {r['err']['rmse']:.5f} | "
          f"{r['err']['rmse'] / nothing['rmse']:.2f} | {r['err']['rmse_clamp1']:.5f} | "
          f"{r['err']['rmse_clamp1'] / nothing['rmse_clamp1']:.2f} | {r['render_s'] - mu['render_s']:.3f} s | "
          f"{r['wall_s']:.2f} | {cpu(r)}" + (f" ({r['cpu_s'] - mu['cpu_s']:.2f})" if "cpu_s" in r else "") + " |")
    for name, label in (("layered", "dof.method=layered (64 samples, default)"),
                        ("isg", "dof.method=isg (64 samples, default)"),
                        ("layered 256", "dof.method=layered, dof.samples=256"),
                        ("isg 256", "dof.method=isg, dof.samples=256")):
        r = isg[name]
        w(f"| **isg** | {label} | {r['err']['rmse']:.5f} | {r['err']['rmse'] / nothing['rmse']:.2f} | "
          f"{r['err']['rmse_clamp1']:.5f} | {r['err']['rmse_clamp1'] / nothing['rmse_clamp1']:.2f} | "
          f"{r['dof_ms']:.1f} ms ({r['gpu_total_ms']:.1f}) | {r['wall_s']:.2f} | {cpu(r)} |")
    w("")
    sw = sorted(bl["sweep"] + [dict(bl[k], f_stop=bl[k]["node"]["f_stop"], blur_max=bl[k]["node"]["blur_max"])
                               for k in ("default", "matched")], key=lambda r: (r["f_stop"], r["blur_max"]))
    w("Blender's f-stop and max blur around those two (error only, one run each; *render s* is the whole "
      "render call, Defocus included, one run, for scale only):\n")
    w("| Defocus f-stop | × matched | max blur | RMSE | of nothing | RMSE clamped | render s |")
    w("|---|---|---|---|---|---|---|")
    for r in sw:
        w(f"| {r['f_stop']:.2f} | {r['f_stop'] / Ln['fstop_matched']:.2f} | {r['blur_max']:g} | "
          f"{r['err']['rmse']:.5f} | {r['err']['rmse'] / nothing['rmse']:.2f} | {r['err']['rmse_clamp1']:.5f} | "
          f"{r['render_s']:.2f} |")
    w("")
    w("Commands (the Blender tree is built by the Python script embedded in bench/blender_defocus.py, "
      "written to a temporary folder):\n")
    w(f"    {bl['command']}")
    w(f"    <json> = {json.dumps(bl['params_example'])}")
    for name in ("layered", "isg"):
        w(f"    {isg[name]['cmd']}")
    w("")
    w("Blender's node: Defocus, Z buffer on (Z = the Image node's `Depth`, Cycles' planar depth, 1e10 on the "
      "background), bokeh circle, angle 0, no gamma correction, preview off, threshold 1 (its default), "
      f"max blur {bl['matched']['node']['blur_max']:g} px (the case's largest CoC radius, "
      f"{Ln['r_max_px']:.1f} px at z = {Ln['z_min']:.3f} m, rounded up, + 1), z scale 1 (unused with the Z buffer); "
      f"the scene camera: {bl['matched']['camera']['lens']:g} mm lens, {bl['matched']['camera']['sensor_width']:g} mm "
      f"sensor, horizontal fit, focus distance {bl['matched']['camera']['focus_distance']:g} m; render size "
      f"{d['size']}, 100 %; Composite with alpha, written as 32-bit float RGBA EXR "
      "(view transform Standard; EXR output is linear).\n")
    w("## What Blender's Defocus does differently\n")
    w(f"- **Its f-stop is not the lens's.** Blender 3.4 turns depth into a blur radius as "
      "r = ½·|a·(s·(1/z_f − 1/z) − 1)| with a = ½·lens/(aspect·sensor)/N and s = min(W,H)·2·lens/sensor, "
      "lens and sensor in millimetres and z in scene units: about lens²·W/(2·N·sensor²)·|1/z_f − 1/z| pixels. "
      "Cycles' thin lens (the reference) gives f²/(2N)·W/sensor·|1/z_f − 1/z| with f and sensor in metres. "
      f"The two differ by 1000/sensor_mm = {Ln['ratio']:.1f}×, whatever the lens: at scene.json's f/1.4 "
      f"Blender asks for a {Ln['r_max_blender_default_px']:.0f} px radius on the nearest surface where the "
      f"lens gives {Ln['r_max_px']:.1f} px, so nearly every pixel hits max blur ({Ln['r_inf_px']:.1f} px at "
      f"infinity on the case's lens). The matched row sets the Defocus f-stop to N·1000/sensor_mm = "
      f"{Ln['fstop_matched']:.2f}, which gives the case's CoC to within the formula's constant ½·a "
      "(0.03 px); the f-stop table above finds Blender's error lowest there. A user matching by eye would "
      "land somewhere near it; the default row is what the node gives when fed the real f-stop.")
    w("- **The circle of confusion is blurred before use** (a Gaussian over the radius map, sigma = "
      "min(128·a, max blur), then the minimum of it and the original), so a near object's radius drops near "
      "its silhouette: foreground blur stops short of the edge.")
    w("- **A gather limited by the pixel's own radius**: each output pixel averages the neighbours whose "
      "radius reaches it, each neighbour's radius first limited to the pixel's own (the minimum of both), "
      "weighted by the bokeh image at the offset (a disc) and not by 1/r² (a neighbour's light is not "
      "spread over its disc's area); the pixel itself counts with weight 1. An in-focus pixel therefore "
      "takes nothing from a blurred foreground in front of it: out-of-focus near objects do not spread over "
      "the sharp surface behind them, and nothing is recovered behind "
      "the foreground (one layer, no occlusion handling). isg's layered method gathers near and far fields "
      "apart and composites the near field over the far by its coverage.")
    w("- **Threshold**: pixels whose radius is under 1 px (the default threshold) are copied unblurred, "
      "and between 1 and 2 px blended linearly with the blurred result. The background's depth (1e10) maps "
      "to max blur; its colour is premultiplied black with alpha 0, as in the reference.")
    w(f"- **Focus breathing**: isg's eq. 15 uses the focusing lens's CoC, z_f/(z_f − f) = "
      f"{Ln['k_isg'] / Ln['k_case']:.3f}× the CoC of Cycles' thin lens (which keeps the pinhole's field of "
      "view and bends rays through the focal plane), so isg's blur is that much larger than the reference's; "
      "Blender's matched f-stop gives Cycles' CoC.")
    w("- **Time**: Blender's compositor is multi-threaded CPU code; isg ran on "
      f"{isg['layered']['device']}" + (" (a CPU Vulkan device: the same 2 cores)" if "llvmpipe" in
                                       isg['layered']['device'] else "") + ".")
    w("")
    return "\n".join(L)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default="build")
    ap.add_argument("--case", default=os.path.join(SHARED_CASES, "dof"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--execution-mode", default="TILED", choices=["TILED", "FULL_FRAME"],
                    help="Blender compositor execution mode (3.4's default: TILED)")
    ap.add_argument("--quiet-load", type=float, default=1.0)
    ap.add_argument("--quiet-wait", type=float, default=1200)
    ap.add_argument("--from-json", action="store_true", help="rewrite the page from bench/out/dof_blender.json")
    a = ap.parse_args()
    os.makedirs(PAGES, exist_ok=True)
    last = os.path.join(OUT, JSON)
    if a.from_json:
        open(PAGE, "w").write(page(json.load(open(last))))
        return
    if not shutil.which(a.blender):
        msg = f"`{a.blender}` is not on this machine's PATH, so Blender's Defocus node was not run."
        print(f"blender_defocus: skipped: {msg}")
        open(PAGE, "w").write(page(json.load(open(last)) if os.path.exists(last) else None, skipped=msg))
        return
    if not os.path.exists(os.path.join(a.case, "cycles_native.exr")):
        msg = f"the shared case {a.case} (cycles_native.exr) is not on this machine."
        print(f"blender_defocus: skipped: {msg}")
        open(PAGE, "w").write(page(json.load(open(last)) if os.path.exists(last) else None, skipped=msg))
        return
    d = measure(a)
    save(JSON, d)
    open(PAGE, "w").write(page(d))
    print(open(PAGE).read())


if __name__ == "__main__":
    main()
