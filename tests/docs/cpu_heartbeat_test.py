#!/usr/bin/env python3
"""scripts/cpu_heartbeat.py: the CPU time of a command's process tree survives the command being
killed (a regeneration stopped by its machine session, issue 38), is exact when it ends, and a
SIGTERM to it (a checkpoint stopping the regeneration) ends the command with an exact line.
The work is a fixed count of shell loop turns, not a time, so a loaded machine (CI's other test)
only slows it: every CPU check compares with the same work timed here directly."""
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import verdict  # noqa: E402

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "cpu_heartbeat.py")
LOOP = "sh -c 'i=0; while [ $i -lt 200000 ]; do i=$((i+1)); done'"
TWO = "for i in 1 2; do %s & done; wait" % LOOP  # two busy grandchildren: the tree, not the child


def fields(path):
    return open(path).read().split()


def cpu(f):
    return float(f[4]) + float(f[5])


def children_cpu():
    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


def wait_for(path, seconds=60):
    end = time.monotonic() + seconds
    while not os.path.exists(path) and time.monotonic() < end:
        time.sleep(0.05)


def main():
    d = tempfile.mkdtemp()
    before = children_cpu()
    subprocess.call(["bash", "-c", TWO])
    ref = children_cpu() - before  # CPU of the two loops, measured directly
    checks = []
    out = d + "/failed.txt"
    rc = subprocess.call([sys.executable, SCRIPT, "--out", out, "--prefix", "S C 2", "--every", "0.3", "--",
                          "bash", "-c", TWO + "; exit 3"])
    f = fields(out)
    checks += [(rc == 3, "exit status is the command's (%d)" % rc),
               (f[:3] == ["S", "C", "2"] and f[6] == "stopped", "a failed command's line says stopped: %s" % f),
               (cpu(f) > 0.8 * ref, "CPU of both grandchildren counted: %s (direct %.2f s)" % (f, ref))]
    out = d + "/ok.txt"
    rc = subprocess.call([sys.executable, SCRIPT, "--out", out, "--prefix", "S C 2", "--", "true"])
    f = fields(out)
    checks += [(rc == 0 and f[6] == "complete", "a command that exits 0 is complete: %s" % f)]
    # A session's end: every process at once, no clean-up; the last heartbeat is what is left.
    out, mark = d + "/killed.txt", d + "/killed.mark"
    t0 = time.monotonic()
    p = subprocess.Popen([sys.executable, SCRIPT, "--out", out, "--prefix", "S C 2", "--every", "0.3", "--",
                          "bash", "-c", TWO + "; touch %s; sleep 60" % mark], start_new_session=True)
    wait_for(mark)
    time.sleep(1.0)  # heartbeats after the loops ended
    os.killpg(p.pid, signal.SIGKILL)
    p.wait()
    f = fields(out)
    checks += [(f[6] == "stopped", "a killed run leaves a 'stopped' line: %s" % f),
               (cpu(f) > 0.8 * ref, "its last heartbeat holds the tree's CPU so far: %s (direct %.2f s)" % (f, ref)),
               (0 < float(f[3]) <= time.monotonic() - t0, "and its wall time: %s" % f)]
    # SIGTERM to the heartbeat alone: passed on to the command, whose shell ends; the final line is
    # written from getrusage, exact, before any heartbeat (every 60 s).
    out, mark = d + "/term.txt", d + "/term.mark"
    p = subprocess.Popen([sys.executable, SCRIPT, "--out", out, "--prefix", "S C 2", "--every", "60", "--",
                          "bash", "-c", "trap 'exit 143' TERM; %s; touch %s; sleep 60 & wait" % (TWO, mark)],
                         start_new_session=True)
    wait_for(mark)
    p.send_signal(signal.SIGTERM)
    rc = p.wait(timeout=30)
    os.killpg(p.pid, signal.SIGKILL)  # the shell's orphaned sleep, which holds the test's output open
    f = fields(out)
    checks += [(rc != 0 and f[6] == "stopped", "SIGTERM stops the command, line 'stopped' (rc %d): %s" % (rc, f)),
               (cpu(f) > 0.8 * ref, "and it holds the command's CPU: %s (direct %.2f s)" % (f, ref))]
    return verdict(checks)


if __name__ == "__main__":
    sys.exit(main())
