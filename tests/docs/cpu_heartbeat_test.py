#!/usr/bin/env python3
"""scripts/cpu_heartbeat.py: the CPU time of a command's process tree survives the command being
killed (a regeneration stopped by its machine session, issue 38), and is exact when it ends."""
import os
import signal
import subprocess
import sys
import tempfile
import time

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "cpu_heartbeat.py")
# Two busy grandchildren for ~1.5 s each under a shell: the tree, not just the direct child.
BUSY = "for i in 1 2; do timeout 1.5 sh -c 'while :; do :; done' & done; wait"


def fields(path):
    return open(path).read().split()


def main():
    d = tempfile.mkdtemp()
    checks = []
    out = d + "/done.txt"
    rc = subprocess.call([sys.executable, SCRIPT, "--out", out, "--prefix", "S C 2", "--every", "0.3", "--",
                          "bash", "-c", BUSY + "; exit 3"])
    f = fields(out)
    checks += [(rc == 3, "exit status is the command's (%d)" % rc),
               (f[:3] == ["S", "C", "2"] and f[6] == "complete", "complete line: %s" % f),
               (float(f[4]) + float(f[5]) > 1.5, "CPU of both grandchildren counted: %s" % f)]
    out = d + "/killed.txt"
    p = subprocess.Popen([sys.executable, SCRIPT, "--out", out, "--prefix", "S C 2", "--every", "0.3", "--",
                          "bash", "-c", BUSY], start_new_session=True)
    time.sleep(1.2)
    os.killpg(p.pid, signal.SIGKILL)  # a session's end: every process at once, no clean-up
    p.wait()
    f = fields(out)
    checks += [(f[6] == "stopped", "a killed run leaves a 'stopped' line: %s" % f),
               (float(f[4]) + float(f[5]) > 0.8, "its last heartbeat holds the tree's CPU so far: %s" % f),
               (0.5 < float(f[3]) < 1.3, "and its wall time: %s" % f)]
    failed = [what for good, what in checks if not good]
    for what in failed:
        print("FAILED: " + what)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
