"""`import isg` (issue 21) against the CLI it mirrors: roles as `isg info --json`, the plan as
`isg run --dry-run`, runs on files and on NumPy arrays bitwise as `isg run` with the same preset
and overrides, and errors as exceptions naming the file, channel or key, with no output left.

Environment: PYTHONPATH holding the module, ISG_BINARY (the isg executable), ISG_SAMPLE."""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import exr_bytes  # noqa: E402
import isg  # noqa: E402

CLI = os.environ["ISG_BINARY"]
SAMPLE = os.environ["ISG_SAMPLE"]
AOVS = os.path.join(SAMPLE, "aovs.exr")
SCENE = os.path.join(SAMPLE, "scene.json")


def cli(*args):
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


@pytest.fixture(scope="module")
def ctx():
    return isg.Context()


@pytest.fixture(scope="module")
def cli_out(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "out.exr"
    cli("run", AOVS, "--scene", SCENE, "-o", out)
    return out


def test_roles_are_isg_info_json():
    want = json.loads(cli("info", AOVS, "--scene", SCENE, "--json"))
    got = isg.roles(AOVS, scene=SCENE)
    assert (got["width"], got["height"]) == (want["width"], want["height"])
    assert got["lights"] == want["lights"] and got["channels"] == want["channels"]
    assert got["camera"] == want["camera"]
    assert set(got["roles"]) == set(want["roles"])
    for role, b in want["roles"].items():
        assert got["roles"][role] == b, role


def test_plan_is_the_dry_run():
    for flags, kw in [([], {}), (["--preset", "film", "--set", "shadows.method=vssm"],
                                 {"preset": "film", "set": ["shadows.method=vssm"]})]:
        text = cli("run", AOVS, "--scene", SCENE, "--dry-run", *flags)
        p = isg.plan(AOVS, scene=SCENE, **kw)
        assert p["text"] == text
        assert p["missing"] == [] and p["passes"] and p["gpu_bytes"] > 0
    vssm = isg.plan(AOVS, scene=SCENE, set={"shadows.method": "vssm"})
    assert any(e["method"] == "vssm" for e in vssm["effects"]), vssm["effects"]


def test_preset_file_and_channel_mapping_as_the_cli(tmp_path, ctx):
    preset = tmp_path / "look.toml"
    preset.write_text('base = "preview"\n[shadows]\nmethod = "hard"\n[output]\ncompression = "zip"\n')
    renamed = {("depth_z" if k == "Z" else k): v for k, v in isg.read_exr(AOVS).items()}
    a, b = tmp_path / "cli.exr", tmp_path / "py.exr"
    cli("run", AOVS, "--scene", SCENE, "-o", a, "--preset", preset, "--compression", "none")
    isg.run(AOVS, b, scene=SCENE, preset=preset, compression="none", context=ctx)
    assert exr_bytes.same(a, b)
    # A renamed depth channel mapped back gives the same composite.
    out = isg.run(renamed, scene=SCENE, preset=preset, channels={"depth": "depth_z"}, context=ctx)
    ref = isg.read_exr(a)
    for c in "RGBA":
        assert out[c].tobytes() == ref[c].tobytes(), c


def test_arrays_are_bitwise_the_file(cli_out, ctx):
    arrays = isg.read_exr(AOVS)
    out = isg.run(arrays, scene=SCENE, context=ctx)
    ref = isg.read_exr(cli_out)
    assert sorted(out) == sorted(ref)
    for name, want in ref.items():
        assert out[name].dtype == want.dtype, name
        assert out[name].shape == (180, 320), name
        assert out[name].tobytes() == want.tobytes(), name
    # float32 (or float64) arrays for half channels: the same values, computed the same way.
    wide = {k: v.astype(np.float64) for k, v in arrays.items()}
    out64 = isg.run(wide, scene=SCENE, context=ctx)
    assert out64["R"].dtype == np.float32
    assert np.array_equal(out64["R"].astype(np.float16), ref["R"])


def test_run_arrays_without_a_context_and_nonfinite_warns(ctx):
    arrays = isg.read_exr(AOVS)
    arrays["Z"] = arrays["Z"].copy()
    arrays["Z"][0, :3] = np.nan
    with pytest.warns(RuntimeWarning, match="channel Z had 3 NaN/Inf"):
        out = isg.run(arrays, scene=SCENE)
    assert np.isfinite(out["R"]).all()


@pytest.mark.parametrize("kw, kind, needle", [
    ({"set": {"shadows.nope": 1}}, isg.ParamError, "shadows.nope"),
    ({"set": {"shadows.method": "bogus"}}, isg.ParamError, "shadows.method"),
    ({"set": ["shadows.method"]}, isg.ParamError, "shadows.method"),
    ({"preset": "no-such-preset"}, isg.ParamError, "no-such-preset"),
    ({"channels": {"depth": "nope"}}, isg.IoError, "nope"),
    ({"channels": {"wobble": "Z"}}, isg.IoError, "wobble"),
    ({"scene": "/nonexistent/scene.json"}, isg.IoError, "/nonexistent/scene.json"),
])
def test_errors_name_the_key_file_or_channel(tmp_path, kw, kind, needle):
    out = tmp_path / "out.exr"
    with pytest.raises(kind, match=needle.replace(".", r"\.")) as e:
        isg.run(AOVS, out, **{"scene": SCENE, **kw})
    assert isinstance(e.value, isg.Error) and isinstance(e.value, RuntimeError)
    assert "\n" not in str(e.value)
    assert os.listdir(tmp_path) == []  # no output, nothing partial


def test_bad_files_and_arrays_name_what_is_wrong(tmp_path, ctx):
    bad = tmp_path / "cut.exr"
    data = open(AOVS, "rb").read()
    bad.write_bytes(data[: len(data) * 2 // 3])
    with pytest.raises(isg.IoError, match="cut.exr"):
        isg.run(bad, tmp_path / "out.exr", scene=SCENE, context=ctx)
    with pytest.raises(isg.IoError, match="missing.exr"):
        isg.roles(tmp_path / "missing.exr")
    assert sorted(os.listdir(tmp_path)) == ["cut.exr"]
    arrays = isg.read_exr(AOVS)
    arrays["Z"] = arrays["Z"][:10]
    with pytest.raises(isg.IoError, match="channel Z"):
        isg.run(arrays, scene=SCENE, context=ctx)
    arrays["Z"] = np.zeros(5)
    with pytest.raises(isg.IoError, match="channel Z: expected a 2-D array"):
        isg.plan(arrays, scene=SCENE)
    del arrays["Z"]
    for c in "RGBA":
        del arrays[c]
    with pytest.raises(isg.IoError, match="arrays: missing required channels for role beauty"):
        isg.run(arrays, scene=SCENE, context=ctx)


def test_no_clobber_and_never_the_input(tmp_path, ctx):
    out = tmp_path / "out.exr"
    out.write_bytes(b"precious")
    with pytest.raises(isg.IoError, match="out.exr"):
        isg.run(AOVS, out, scene=SCENE, no_clobber=True, context=ctx)
    assert out.read_bytes() == b"precious"
    copy = tmp_path / "in.exr"
    shutil.copy(AOVS, copy)
    with pytest.raises(isg.IoError, match="input"):
        isg.run(copy, copy, scene=SCENE, context=ctx)
    assert copy.read_bytes() == open(AOVS, "rb").read()
