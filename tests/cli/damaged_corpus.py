"""Issue 54: a damaged file costs no more than its bytes allow. A scripted corpus of crafted
inputs under 1 KiB (tests/support/exr_craft.py), for every compression:

- a header claiming a 100663297x1 data window over one 200-byte chunk (the issue's file);
- a chunk table cut short, and one with an offset past the end of the file;
- a chunk listed twice in the table (so one is missing);
- a tiled part whose one tile claims a level far larger than its bytes.

`isg info` on each, and `isg run` on each compression's size claim and on each kind of damage
once, must exit non-zero with one line on stderr naming the file,
write no output, and stay within 50 MB of the process's own peak resident memory (the same
command on a valid file of the same size: the Vulkan driver and the libraries). Wall time is
reported, not asserted (a benchmark measures; a hang guard of 20 s stands).

The corpus itself is exr_craft.damaged_corpus (scripts/fuzz.sh seeds the EXR harness with it).

Usage: python3 damaged_corpus.py ISG_BINARY [-v]"""
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import exr_craft as c  # noqa: E402

isg = sys.argv[1]
tmp = tempfile.mkdtemp(prefix="isg-damaged-")
failures = []


def measure(args):
    """Runs isg with args; returns (exit code, stderr, wall s, peak RSS MiB) of that process."""
    t0 = time.monotonic()
    p = subprocess.Popen([isg] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        _, err = p.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        return None, "hang (20 s)", 20.0, 0.0
    wall = time.monotonic() - t0
    # communicate() reaped it; its rusage is what the children's total gained from it alone
    return p.returncode, err, wall, None


def rss_of(args):
    """Peak RSS (MiB) and wall of one isg run, from wait4 on that child alone."""
    t0 = time.monotonic()
    pid = os.fork()
    if pid == 0:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        err = os.open(os.path.join(tmp, "stderr"), os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
        os.dup2(err, 2)
        os.execv(isg, [isg] + args)
    deadline = t0 + 20
    while True:
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() > deadline:
            os.kill(pid, 9)
            _, status, usage = os.wait4(pid, 0)
            break
        time.sleep(0.01)
    wall = time.monotonic() - t0
    with open(os.path.join(tmp, "stderr")) as f:
        err = f.read()
    code = os.waitstatus_to_exitcode(status)
    return code, err, wall, usage.ru_maxrss / 1024.0


try:
    # The floors: the same commands on a valid file of the same size class.
    valid = os.path.join(tmp, "valid.exr")
    flat = bytes(8 * 2 * 4)  # 8x1 half RGBA, uncompressed
    with open(valid, "wb") as f:
        f.write(c.scanline_file((0, 0, 7, 0), "none", [(0, flat)]))
    floors = {}
    for cmd in ("info", "run"):
        args = [cmd, valid] + (["-o", os.path.join(tmp, "valid-out.exr")] if cmd == "run" else [])
        code, err, wall, rss = rss_of(args)
        floors[cmd] = rss
        print(f"floor: isg {cmd} on an 8x1 valid file: exit {code}, {wall:.2f} s, peak {rss:.0f} MiB")
    worst = {"info": (0.0, 0.0), "run": (0.0, 0.0)}
    n = 0
    for name, b in c.damaged_corpus():
        path = os.path.join(tmp, name + ".exr")
        with open(path, "wb") as f:
            f.write(b)
        if len(b) >= 1024:
            failures.append(f"{name}: {len(b)} bytes, not under 1 KiB")
        # isg info on every file; isg run on every compression's size claim and on each other
        # kind of damage once (zip), which keeps the suite's time down: run differs from info
        # only after the structure walk that refuses all of them.
        cmds = ("info", "run") if name.startswith("claims-") or name.endswith("-zip") else ("info",)
        for cmd in cmds:
            out = os.path.join(tmp, name + "-out.exr")
            args = [cmd, path] + (["-o", out] if cmd == "run" else [])
            code, err, wall, rss = rss_of(args)
            lines = err.strip().splitlines()
            # Refused by the check meant for it, not by an earlier limit.
            kind = name.rsplit("-", 1)[0]
            want = {"claims": ("can hold (at most", "uncompressed pixels take"),
                    "tile-claims": ("can hold (at most", "uncompressed pixels take"),
                    "table-cut": ("offset tables need",), "offset-past-end": ("past the end of the file",),
                    "listed-twice": ("listed twice",)}[kind]
            ok = (code not in (0, None) and len(lines) == 1 and lines[0].startswith("isg: error: ")
                  and name + ".exr" in lines[0] and any(w in lines[0] for w in want)
                  and not os.path.exists(out) and rss <= floors[cmd] + 50)
            worst[cmd] = (max(worst[cmd][0], wall), max(worst[cmd][1], rss))
            n += 1
            if not ok:
                failures.append(f"isg {cmd} {name}.exr ({len(b)} bytes): exit {code}, {wall:.2f} s, "
                                f"{rss:.0f} MiB, stderr {err.strip()!r}")
            elif "-v" in sys.argv:
                print(f"ok: isg {cmd} {name}.exr: {wall:.2f} s, {rss:.0f} MiB: {lines[0]}")
    for cmd in ("info", "run"):
        print(f"isg {cmd}: slowest {worst[cmd][0]:.2f} s, largest peak {worst[cmd][1]:.0f} MiB "
              f"(floor {floors[cmd]:.0f} MiB, bound floor + 50)")
    print(f"{n} runs on the crafted files")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
for f in failures:
    print("FAIL:", f)
print("PASS" if not failures else f"{len(failures)} FAILED")
sys.exit(1 if failures else 0)
