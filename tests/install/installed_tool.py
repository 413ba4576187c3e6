"""Issue 55: the Debian package holds everything a user runs, and it runs with no build or source
folder on any path.

Builds the .deb with cpack from the finished build, unpacks it (dpkg-deb -x) into a new folder
outside the build tree, then, with a clean environment (PATH the unpacked usr/bin and the
system's, HOME a new folder, no ISG_* variables) and that folder as the working directory:

- the package declares its dependencies (dpkg-shlibdeps' libraries, a Vulkan driver, Python);
- `isg --version` prints the version and the commit, `isg presets` finds the installed presets;
- the installed `isg run` on the installed sample, with a shipped preset, writes what the build's
  `isg run` writes, bitwise (every byte but capDate: tests/support/exr_bytes.py);
- `import isg` from the unpacked dist-packages does the same from Python;
- `man` renders the installed isg(1), and the bash completion completes options and keys.

Usage: python3 installed_tool.py BUILD_DIR SOURCE_DIR (Debian's python3: it imports the module)."""
import glob
import os
import shutil
import subprocess
import sys
import tempfile

build, source = map(os.path.abspath, sys.argv[1:3])
sys.path.insert(0, os.path.join(source, "tests", "support"))
import exr_bytes  # noqa: E402

tmp = tempfile.mkdtemp(prefix="isg-install-", dir="/tmp")
failures = []


def check(ok, what):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def run(cmd, env=None, cwd=None):
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=cwd)
    if p.returncode != 0:
        sys.exit(f"FAIL: {' '.join(cmd)} exited {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p.stdout


try:
    # The package, from the finished build.
    run(["cpack", "-G", "DEB", "-B", os.path.join(tmp, "pkg")], cwd=build)
    debs = glob.glob(os.path.join(tmp, "pkg", "isg_*_amd64.deb"))
    check(len(debs) == 1, f"cpack -G DEB wrote one isg_<version>_amd64.deb: {debs}")
    deb = debs[0]
    depends = run(["dpkg-deb", "-f", deb, "Depends"])
    for d in ["libvulkan1", "libopenimageio2.4", "libopenexr-3-1-30", "libopencolorio2.1",
              "mesa-vulkan-drivers | vulkan-icd", "python3 (>= 3.", "python3-numpy"]:
        check(d in depends, f"Depends names {d}")
    root = os.path.join(tmp, "root")
    run(["dpkg-deb", "-x", deb, root])
    usr = os.path.join(root, "usr")
    for f in ["bin/isg", "bin/isg-synth", "bin/isg-exrcheck", "share/isg/presets/film.toml",
              "share/isg/samples/contact/aovs.exr", "share/man/man1/isg.1",
              "share/man/man1/isg-synth.1", "share/man/man1/isg-exrcheck.1",
              "share/bash-completion/completions/isg", "share/doc/isg/README.md",
              "share/doc/isg/parameters.md"]:
        check(os.path.exists(os.path.join(usr, f)), f"the package holds usr/{f}")
    modules = glob.glob(os.path.join(usr, "lib", "python3", "dist-packages", "isg.cpython-*.so"))
    check(len(modules) == 1, "the package holds the module in usr/lib/python3/dist-packages")

    # A clean environment: nothing of the build or the source tree on any path.
    home, work = os.path.join(tmp, "home"), os.path.join(tmp, "work")
    os.makedirs(home)
    os.makedirs(work)
    env = {"PATH": f"{usr}/bin:/usr/bin:/bin", "HOME": home, "LANG": "C.UTF-8"}
    version = run(["isg", "--version"], env=env, cwd=work)
    check(version.startswith("isg ") and "(commit " in version and "Vulkan" in version,
          f"isg --version: {version.splitlines()[0]} / {version.splitlines()[-1]}")
    presets = run(["isg", "presets"], env=env, cwd=work)
    check("film" in presets and "preview" in presets, "isg presets lists the installed presets")

    sample = os.path.join(usr, "share", "isg", "samples", "contact")
    aovs, scene = os.path.join(sample, "aovs.exr"), os.path.join(sample, "scene.json")
    flags = ["--scene", scene, "--preset", "preview", "--set", "shadows.method=pcss"]
    built = os.path.join(tmp, "built.exr")
    run([os.path.join(build, "cli", "isg"), "run", aovs, "-o", built] + flags)
    installed = os.path.join(work, "installed.exr")
    run(["isg", "run", aovs, "-o", installed] + flags, env=env, cwd=work)
    check(exr_bytes.same(built, installed),
          "the installed isg run (preset preview) writes the build's output, bitwise")

    py_env = dict(env, PYTHONPATH=os.path.dirname(modules[0]))
    py_out = os.path.join(work, "python.exr")
    code = ("import isg, sys; print(isg.__file__); "
            f"isg.run({aovs!r}, {py_out!r}, scene={scene!r}, preset='preview', "
            "set={'shadows.method': 'pcss'})")
    where = run(["/usr/bin/python3", "-c", code], env=py_env, cwd=work).strip()
    check(where.startswith(usr), f"import isg from the package: {where}")
    check(exr_bytes.same(built, py_out), "isg.run from the installed module writes the same, bitwise")

    # Pixels are decoded in the installed isg-exrcheck child (the layout finds it beside the
    # prefix): its wording, not the in-process decoder's, for pixel data OpenEXR cannot decode.
    sys.path.insert(0, os.path.join(source, "tests", "support"))
    import exr_craft  # noqa: E402
    damaged = os.path.join(work, "damaged.exr")
    with open(damaged, "wb") as f:
        f.write(exr_craft.scanline_file((0, 0, 7, 15), "zip", [(0, bytes(range(40)))]))
    p = subprocess.run(["isg", "run", damaged, "-o", os.path.join(work, "d.exr")], env=env, cwd=work,
                       capture_output=True, text=True)
    check(p.returncode == 1 and "damaged EXR" in p.stderr, f"the installed isg decodes in its child: {p.stderr.strip()}")
    code = f"import isg\ntry:\n    isg.run({damaged!r}, {os.path.join(work, 'e.exr')!r})\nexcept isg.Error as e:\n    print(e)"
    msg = run(["/usr/bin/python3", "-c", code], env=py_env, cwd=work)
    check("damaged EXR" in msg, f"the installed module decodes in the child too: {msg.strip()}")

    page = run(["man", "-l", os.path.join(usr, "share", "man", "man1", "isg.1")],
               env=dict(env, MANWIDTH="100"))
    check("isg run" in page and "ENVIRONMENT" in page and "ISG_PRESET_PATH" in page,
          "man isg renders (COMMANDS, ENVIRONMENT)")

    completion = os.path.join(usr, "share", "bash-completion", "completions", "isg")

    def complete(*words):
        script = (f"source {completion}; COMP_WORDS=({' '.join(words)}); "
                  f"COMP_CWORD={len(words) - 1}; _isg; printf '%s\\n' \"${{COMPREPLY[@]}}\"")
        return run(["bash", "-c", script], env=env, cwd=work).split()

    check("--preset" in complete("isg", "run", "--pre"), "completion: isg run --pre -> --preset")
    check("shadows.method=" in complete("isg", "run", "--set", "shadows.meth"),
          "completion: isg run --set shadows.meth -> shadows.method=")
    check("film" in complete("isg", "run", "--preset", "fi"), "completion: --preset fi -> film")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

print("PASS" if not failures else f"{len(failures)} FAILED")
sys.exit(1 if failures else 0)
