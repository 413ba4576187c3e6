"""Issue 21's done-means: `import isg` runs the bundled sample (samples/contact) and writes what
`isg run` writes, bitwise (every byte but the capDate header value, the time of writing), with
the default preset and with a preset plus overrides; with NumPy, the arrays path too (each
channel bitwise the CLI file's). Runs with the plain `python3`: no pytest, NumPy optional.

Environment: PYTHONPATH holding the module, ISG_BINARY (the isg executable), ISG_SAMPLE."""
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import exr_bytes  # noqa: E402
import isg  # noqa: E402

cli = os.environ["ISG_BINARY"]
sample = os.environ["ISG_SAMPLE"]
aovs, scene = os.path.join(sample, "aovs.exr"), os.path.join(sample, "scene.json")
tmp = tempfile.mkdtemp(prefix="isg-python-")
print(f"isg {isg.__version__} from {isg.__file__}, Python {sys.version.split()[0]} ({sys.executable})")

ctx = isg.Context()
cases = [([], {}),
         (["--preset", "preview", "--set", "shadows.method=pcss", "--set", "dof.method=isg",
           "--set", "reflections.search_reach=false"],
          {"preset": "preview",
           "set": {"shadows.method": "pcss", "dof.method": "isg", "reflections.search_reach": False}})]
for i, (flags, kwargs) in enumerate(cases):
    a, b = os.path.join(tmp, f"cli{i}.exr"), os.path.join(tmp, f"py{i}.exr")
    subprocess.run([cli, "run", aovs, "--scene", scene, "-o", a] + flags, check=True,
                   stdout=subprocess.DEVNULL)
    info = isg.run(aovs, b, scene=scene, context=ctx, **kwargs)
    assert info["output"] == b and "R" in info["channels"], info
    assert exr_bytes.same(a, b), f"isg.run({kwargs}) differs from isg run {' '.join(flags)}"
    print(f"ok: isg.run(aovs, out, scene=..., {kwargs}) == isg run {' '.join(flags)} (bitwise)")

try:
    import numpy as np
except ImportError:
    print("numpy absent for this interpreter: the arrays path is tested by python.pytest")
else:
    out = isg.run(isg.read_exr(aovs), scene=scene, context=ctx)
    ref = isg.read_exr(os.path.join(tmp, "cli0.exr"))
    assert sorted(out) == sorted(ref), (sorted(out), sorted(ref))
    for name, want in ref.items():
        assert out[name].dtype == want.dtype and out[name].tobytes() == want.tobytes(), name
    print(f"ok: isg.run(arrays) == isg run, {len(ref)} channels bitwise")
print("PASS")
