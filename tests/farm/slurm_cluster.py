#!/usr/bin/env python3
"""`isg farm submit` on a real one-node Slurm cluster (issue 21).

Starts munged, slurmctld and slurmd on localhost without systemd, everything in a temporary
folder (its own munge key and socket, a slurm.conf with NodeName=localhost from `slurmd -C`,
proctrack/linuxproc, task/none, no accounting, ports picked free), submits a 24-frame isg-synth
sequence numbered 1001-1024 in chunks with one corrupt frame, waits, and checks:

- every good frame is bitwise the file a local `isg run` of the same frames writes (every
  byte but the capDate header value, the time of writing);
- the bad frame is reported (summary, `isg farm status --json`, exit 3), has no output, and
  nothing partial is left in the output folder; every task left its log and result file;
- the retry with --skip-existing after the frame is fixed submits that frame only, leaves the
  others untouched and writes it bitwise as a local run does;
- Slurm itself refuses `--array=1001-1024` here (the default MaxArraySize), which is why task
  ids map to frame ranges.

Then it stops exactly the daemons it started, by their pids. Exit 77 (ctest's skip) where the
Slurm or munge programs are absent or the cluster does not come up (e.g. not root).
"""
import argparse
import concurrent.futures
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import exr_bytes  # noqa: E402

SKIP = 77
SBIN = ["/usr/sbin", "/sbin", "/usr/local/sbin"]


def which(prog):
    path = os.environ.get("PATH", "") + os.pathsep + os.pathsep.join(SBIN)
    return shutil.which(prog, path=path)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def tail(path, n=15):
    try:
        with open(path, errors="replace") as f:
            return "".join(f.readlines()[-n:])
    except OSError:
        return "(no %s)\n" % path


class Cluster:
    """munged + slurmctld + slurmd in `root`, run in the foreground as children of this process."""

    def __init__(self, root):
        self.root = root
        self.procs = []  # (name, Popen), in start order
        self.env = dict(os.environ, SLURM_CONF=os.path.join(root, "slurm.conf"))

    def start(self):
        r = self.root
        os.chmod(r, 0o755)  # munged wants every folder above its socket searchable
        for d in ("munge", "run", "state", "spool", "log"):
            os.makedirs(os.path.join(r, d))
        os.chmod(os.path.join(r, "munge"), 0o700)
        key = os.path.join(r, "munge", "munge.key")
        with open(key, "wb") as f:
            f.write(os.urandom(1024))
        os.chmod(key, 0o400)
        self.sock = os.path.join(r, "run", "munge.sock")
        self.spawn("munged", [which("munged"), "--foreground", "--key-file=" + key,
                              "--socket=" + self.sock, "--pid-file=" + os.path.join(r, "run", "munged.pid"),
                              "--log-file=" + os.path.join(r, "log", "munged.log"),
                              "--seed-file=" + os.path.join(r, "munge", "seed")])
        if not self.until(lambda: os.path.exists(self.sock), 10):
            return "munged did not start:\n" + tail(os.path.join(r, "log", "munged.log"))
        user = subprocess.run(["id", "-un"], capture_output=True, text=True).stdout.strip()
        # The node as `slurmd -C` sees it, renamed localhost; RealMemory left out (1 MB by default)
        # so a little less free memory at registration never drains the node.
        probe = subprocess.run([which("slurmd"), "-C"], capture_output=True, text=True)
        node = [w for w in probe.stdout.split("\n")[0].split()
                if not w.startswith(("NodeName=", "RealMemory="))]
        if probe.returncode != 0 or not node:
            return "slurmd -C failed: " + probe.stderr.strip()
        conf = f"""ClusterName=isgtest
SlurmctldHost=localhost
SlurmctldPort={free_port()}
SlurmdPort={free_port()}
SlurmUser={user}
SlurmdUser={user}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.sock}
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/run/slurmctld.pid
SlurmdPidFile={r}/run/slurmd.pid
SlurmctldLogFile={r}/log/slurmctld.log
SlurmdLogFile={r}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
SwitchType=switch/none
NodeName=localhost {" ".join(node)} State=UNKNOWN
PartitionName=isg Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""
        with open(self.env["SLURM_CONF"], "w") as f:
            f.write(conf)
        self.spawn("slurmctld", [which("slurmctld"), "-D", "-f", self.env["SLURM_CONF"]])
        self.spawn("slurmd", [which("slurmd"), "-D", "-N", "localhost", "-f", self.env["SLURM_CONF"]])

        def idle():
            for name, p in self.procs:
                if p.poll() is not None:
                    raise RuntimeError(f"{name} exited with {p.returncode}")
            q = self.slurm(["sinfo", "--noheader", "--Node", "--format=%N %t"])
            return q.returncode == 0 and "localhost idle" in q.stdout
        try:
            if self.until(idle, 30):
                return None
        except RuntimeError as e:
            why = str(e)
        else:
            why = "the node did not come up idle in 30 s"
        return (why + "\nslurmctld.log:\n" + tail(os.path.join(r, "log", "slurmctld.log")) +
                "slurmd.log:\n" + tail(os.path.join(r, "log", "slurmd.log")) +
                "stdout/stderr:\n" + tail(os.path.join(r, "log", "slurmctld.out")) +
                tail(os.path.join(r, "log", "slurmd.out")))

    def spawn(self, name, argv):
        out = open(os.path.join(self.root, "log", name + ".out"), "w")
        self.procs.append((name, subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT,
                                                  stdin=subprocess.DEVNULL, env=self.env)))

    @staticmethod
    def until(cond, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            if cond():
                return True
            time.sleep(0.2)
        return False

    def slurm(self, argv, **kw):
        return subprocess.run(argv, capture_output=True, text=True, env=self.env, **kw)

    def stop(self):
        """Cancels what is still queued, then ends the daemons this object started, newest first."""
        if any(p.poll() is None for n, p in self.procs if n == "slurmctld"):
            self.slurm(["scancel", "--user", subprocess.run(["id", "-un"], capture_output=True,
                                                            text=True).stdout.strip()])
        for name, p in reversed(self.procs):
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(15)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
            print(f"stopped {name} (pid {p.pid}, exit {p.returncode})")
        return [p.pid for _, p in self.procs]


def check(cond, what):
    if not cond:
        raise AssertionError(what)
    print("ok:", what)


def run(argv, env, expect=None, **kw):
    t = time.monotonic()
    r = subprocess.run([str(a) for a in argv], capture_output=True, text=True, env=env, **kw)
    print(f"$ {' '.join(str(a) for a in argv)}   # exit {r.returncode}, {time.monotonic() - t:.1f} s")
    sys.stdout.write(r.stdout)
    sys.stdout.write("".join("  | " + line + "\n" for line in r.stderr.splitlines()))
    if expect is not None and r.returncode != expect:
        raise AssertionError(f"exit {r.returncode}, expected {expect}")
    return r


def frames_test(c, isg, synth, work):
    env = c.env
    # 24 frames of the moving contact scene, numbered 1001-1024 as on a film.
    for d in ("in", "out", "local", "gen"):
        os.makedirs(os.path.join(work, d))
    t = time.monotonic()

    def generate(k):
        gen = os.path.join(work, "gen", str(k))
        subprocess.run([synth, "contact", "--frame", str(k), "--out", gen, "--width", "64", "--height",
                        "36", "--no-refs", "--shadowmap-size", "64", "--threads", "1"],
                       check=True, capture_output=True)
        shutil.copy(os.path.join(gen, "aovs.exr"), os.path.join(work, "in", f"shot.{1000 + k}.exr"))
    with concurrent.futures.ThreadPoolExecutor(4) as pool:  # mostly process start-up
        list(pool.map(generate, range(1, 25)))
    print(f"generated 24 frames (64x36) in {time.monotonic() - t:.1f} s")
    scene = os.path.join(work, "gen", "1", "scene.json")
    bad = os.path.join(work, "in", "shot.1012.exr")
    size = os.path.getsize(bad)
    with open(bad, "r+b") as f:
        f.truncate(size * 2 // 3)  # cut inside the pixel data

    # Slurm's own limit: frame numbers as array indices are refused out of the box.
    r = c.slurm(["sbatch", "--array=1001-1024", "--wrap", "true"])
    check(r.returncode != 0 and "array" in r.stderr.lower(),
          "sbatch --array=1001-1024 is refused (MaxArraySize 1001): " + r.stderr.strip())

    logs = os.path.join(work, "logs")
    submit = [isg, "farm", "submit", os.path.join(work, "in", "shot.####.exr"), "-o",
              os.path.join(work, "out", "shot.####.exr"), "--scene", scene, "--frames", "1001-1024",
              "--chunk", "5", "--max-parallel", "2", "--log-dir", logs, "--wait", "--poll", "0.5"]
    t = time.monotonic()
    r = run(submit, env, expect=3)
    job_s = time.monotonic() - t
    check("failed frames: 1012\n" in r.stdout and "frame 1012 (task 2): " in r.stdout and
          "shot.1012.exr" in r.stdout, "the summary names frame 1012 and its file")
    check("23 written, 0 skipped (existing), 1 failed" in r.stdout, "23 frames written, 1 failed")
    st = run([isg, "farm", "status", logs, "--json"], env, expect=3)
    s = json.loads(st.stdout)
    check([f["frame"] for f in s["failed"]] == [1012] and s["written"] == 23 and len(s["tasks"]) == 5 and
          [t["exit"] for t in s["tasks"]] == [0, 0, 3, 0, 0], "isg farm status --json agrees")
    for t in s["tasks"]:
        check(os.path.getsize(t["log"]) > 0 and
              f"task {t['task']} on " in open(t["log"]).read(), f"task {t['task']} ({t['frames']}) left its log")

    # The same frames run here, in one process.
    run([isg, "run", os.path.join(work, "in", "shot.####.exr"), "-o",
         os.path.join(work, "local", "shot.####.exr"), "--scene", scene, "--frames", "1001-1024",
         "--keep-going"], env, expect=3)
    good = [f for f in range(1001, 1025) if f != 1012]
    same = [f for f in good if exr_bytes.same(os.path.join(work, "out", f"shot.{f}.exr"),
                                              os.path.join(work, "local", f"shot.{f}.exr"))]
    check(same == good, "all 23 good frames are bitwise the local run's files (all but capDate)")
    left = sorted(os.listdir(os.path.join(work, "out")))
    check(left == [f"shot.{f}.exr" for f in good], "no output for 1012 and nothing partial in out/")

    # Retry: fix the frame, submit the same range with --skip-existing.
    shutil.copy(os.path.join(work, "gen", "12", "aovs.exr"), bad)
    before = {f: os.stat(os.path.join(work, "out", f"shot.{f}.exr")).st_mtime_ns for f in good}
    t = time.monotonic()
    r = run(submit + ["--skip-existing"], env, expect=0)
    retry_s = time.monotonic() - t
    check("1 frame in 1 task: 1 written" in r.stdout, "the retry ran frame 1012 only")
    check(all(os.stat(os.path.join(work, "out", f"shot.{f}.exr")).st_mtime_ns == before[f] for f in good),
          "the retry left the 23 other outputs untouched")
    run([isg, "run", os.path.join(work, "in", "shot.####.exr"), "-o",
         os.path.join(work, "local", "shot.####.exr"), "--scene", scene, "--frames", "1012"], env, expect=0)
    check(exr_bytes.same(os.path.join(work, "out", "shot.1012.exr"),
                         os.path.join(work, "local", "shot.1012.exr")),
          "the retried frame is bitwise the local run's")
    r = run(submit + ["--skip-existing"], env, expect=0)
    check("nothing to do: all 24 outputs exist" in r.stdout, "a third submission submits nothing")
    return job_s, retry_s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--isg", required=True)
    ap.add_argument("--synth", required=True)
    ap.add_argument("--keep", action="store_true", help="keep the temporary folder")
    a = ap.parse_args()
    missing = [p for p in ("munged", "munge", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo", "scancel")
               if not which(p)]
    if missing:
        print("SKIP: not installed: " + " ".join(missing) + " (scripts/setup.sh test installs them)")
        return SKIP
    # A timeout (ctest's SIGTERM) or ^C still stops the daemons, in the finally below.
    def stop_on(signum, frame):
        raise SystemExit(f"signal {signum}")
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, stop_on)
    t0 = time.monotonic()
    root = tempfile.mkdtemp(prefix="isg-slurm-")
    c = Cluster(root)
    ok = False
    try:
        why = c.start()
        if why:
            print("SKIP: the one-node Slurm cluster did not start: " + why)
            ok = True  # nothing to keep
            return SKIP
        up_s = time.monotonic() - t0
        print(f"cluster up in {up_s:.1f} s (munged, slurmctld, slurmd: pids "
              f"{', '.join(str(p.pid) for _, p in c.procs)}; {root})")
        # Tasks run with the submitter's environment: sbatch's default --export=ALL.
        job_s, retry_s = frames_test(c, a.isg, a.synth, os.path.join(root, "work"))
        ok = True
    finally:
        pids = c.stop()
        for pid in pids:
            try:
                os.kill(pid, 0)
                alive = True
            except ProcessLookupError:
                alive = False
            if alive:
                print(f"pid {pid} still running")
                ok = False
        if ok and not a.keep:
            shutil.rmtree(root, ignore_errors=True)
        else:
            print("kept " + root)
    print(f"PASS in {time.monotonic() - t0:.1f} s: cluster start {up_s:.1f} s, 24-frame job "
          f"{job_s:.1f} s, retry {retry_s:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
