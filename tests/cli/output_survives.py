"""Issue 54: the output survives what farms do to it. With the bundled sample as input:

- a full disk: `isg run` under a 16 KiB file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored: writes
  fail with EFBIG as with ENOSPC) over an existing output: exit 1, one line naming the output,
  the old file byte for byte, no temporary left;
- a kill: SIGKILL as soon as the write's temporary appears, and at delays spread over the run:
  the target is each time the old file or the new one whole (bitwise the reference run's, every
  byte but capDate); a later run removes what the killed writers left;
- two writers on one output, with different settings: the target is whole and one of the two;
  with --no-clobber on a missing target, exactly one wins and the other says why.

Usage: python3 output_survives.py ISG_BINARY"""
import glob
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "support"))
import exr_bytes  # noqa: E402

isg = sys.argv[1]
sample = os.path.join(here, "..", "..", "samples", "contact")
aovs, scene = os.path.join(sample, "aovs.exr"), os.path.join(sample, "scene.json")
tmp = tempfile.mkdtemp(prefix="isg-survive-")
env = dict(os.environ, ISG_PIPELINE_CACHE="off")
failures = []


def check(ok, what):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def cmd(out, *extra):
    return [isg, "run", aovs, "--scene", scene, "-o", out, "--set", "limits.check_seconds=0", *extra]


def temps(folder):
    return [p for p in glob.glob(os.path.join(folder, ".*.tmp*")) if os.path.isfile(p)]


try:
    # References: the new output of each setting, and an "old" file the target holds before.
    ref_a, ref_b = os.path.join(tmp, "ref_a.exr"), os.path.join(tmp, "ref_b.exr")
    subprocess.run(cmd(ref_a, "--set", "shadows.method=pcss"), check=True, env=env, capture_output=True)
    subprocess.run(cmd(ref_b, "--set", "shadows.method=hard"), check=True, env=env, capture_output=True)
    old = open(ref_b, "rb").read()

    # A full disk.
    d = os.path.join(tmp, "full")
    os.makedirs(d)
    target = os.path.join(d, "out.exr")
    open(target, "wb").write(old)
    shell = "trap '' XFSZ; ulimit -f 16; exec \"$@\""
    p = subprocess.run(["bash", "-c", shell, "bash"] + cmd(target, "--set", "shadows.method=pcss"),
                       env=env, capture_output=True, text=True)
    lines = p.stderr.strip().splitlines()
    check(p.returncode == 1 and len(lines) == 1 and "out.exr: cannot write" in lines[0],
          f"full disk: exit {p.returncode}, {lines}")
    check(open(target, "rb").read() == old, "full disk: the old output is intact, byte for byte")
    check(not temps(d), f"full disk: no temporary left ({temps(d)})")

    # Kills: as soon as the write's temporary appears, then at delays over the whole run.
    d = os.path.join(tmp, "kill")
    os.makedirs(d)
    target = os.path.join(d, "out.exr")
    t0 = time.monotonic()
    subprocess.run(cmd(os.path.join(tmp, "timing.exr"), "--set", "shadows.method=pcss"), check=True, env=env,
                   capture_output=True)
    run_s = time.monotonic() - t0
    mid_write = 0
    outcomes = {"old": 0, "new": 0}
    delays = [run_s * k / 12 for k in range(1, 13)] + [None] * 6  # None: at the temporary
    for delay in delays:
        open(target, "wb").write(old)
        before = set(temps(d))
        proc = subprocess.Popen(cmd(target, "--set", "shadows.method=pcss"), env=env,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        start = time.monotonic()
        while proc.poll() is None:
            if delay is None and set(temps(d)) - before:
                break
            if delay is not None and time.monotonic() - start >= delay:
                break
            time.sleep(0.0005)
        killed = proc.poll() is None
        if killed:
            proc.send_signal(signal.SIGKILL)
        proc.wait()
        if killed and delay is None and set(temps(d)) - before:
            mid_write += 1
        now = open(target, "rb").read()
        if now == old:
            outcomes["old"] += 1
        elif exr_bytes.same(target, ref_a):
            outcomes["new"] += 1
        else:
            check(False, f"kill after {delay}: the target is neither the old file nor the new one")
    check(mid_write >= 3, f"kills landed mid-write {mid_write} times of 6 (the temporary present)")
    check(outcomes["old"] + outcomes["new"] == len(delays),
          f"after {len(delays)} kills the target was whole each time: old {outcomes['old']}, new {outcomes['new']}")
    left = temps(d)
    subprocess.run(cmd(target, "--set", "shadows.method=pcss"), check=True, env=env, capture_output=True)
    check(bool(left) and not temps(d) and exr_bytes.same(target, ref_a),
          f"a later run removed the {len(left)} temporaries the killed writers left and wrote the output")

    # Two writers on one output.
    d = os.path.join(tmp, "two")
    os.makedirs(d)
    target = os.path.join(d, "out.exr")
    for round_ in range(3):
        ps = [subprocess.Popen(cmd(target, "--set", f"shadows.method={m}"), env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True) for m in ("pcss", "hard")]
        codes = [p.wait() for p in ps]
        whole = exr_bytes.same(target, ref_a) or exr_bytes.same(target, ref_b)
        check(codes == [0, 0] and whole and not temps(d),
              f"two writers, round {round_}: both exit 0, the target whole and one of the two")
    target = os.path.join(d, "noclobber.exr")
    ps = [subprocess.Popen(cmd(target, "--no-clobber", "--set", f"shadows.method={m}"), env=env,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True) for m in ("pcss", "hard")]
    results = [(p.wait(), p.stderr.read().strip()) for p in ps]
    winners = [i for i, (c, _) in enumerate(results) if c == 0]
    loser_msgs = [e for c, e in results if c != 0]
    check(len(winners) == 1 and exr_bytes.same(target, [ref_a, ref_b][winners[0]]) and
          len(loser_msgs) == 1 and "--no-clobber" in loser_msgs[0] and not temps(d),
          f"two --no-clobber writers: one wins, the other: {loser_msgs}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
print("PASS" if not failures else f"{len(failures)} FAILED")
sys.exit(1 if failures else 0)
