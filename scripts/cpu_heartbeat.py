#!/usr/bin/env python3
"""Run a command and keep its wall and CPU time in a file that survives the command being killed.

    cpu_heartbeat.py --out FILE --prefix "START COMMIT JOBS" [--every 30] -- CMD ARGS...

Every --every seconds FILE is rewritten (atomically) with one line:
    START COMMIT JOBS WALL_S USER_S SYS_S stopped
where USER_S / SYS_S sum the process tree of CMD: for every live descendant its own time plus the
time of the children it has reaped (/proc/PID/stat fields utime, stime, cutime, cstime), so no
second is counted twice. When CMD ends, the last line holds getrusage(RUSAGE_CHILDREN), which is
exact, and ends with "complete" (CMD exited 0) or "stopped" (it did not). A regeneration that its
machine's session kills (issue 38: a stop's processes end with the stop) thus leaves its time to at
most --every seconds; the caller appends FILE to its time log. SIGTERM / SIGINT are passed on to
CMD (snakemake then ends its jobs), and the line written when it has ended is exact: that is how
scripts/regen-checkpoint.py stops a regeneration before it saves it. Exit status: CMD's.
"""
import argparse
import os
import resource
import signal
import subprocess
import sys
import time

TICK = os.sysconf("SC_CLK_TCK")


def tree_cpu(root):
    """User and system seconds of root and its live descendants, with their reaped children."""
    stats = {}
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % name) as f:
                text = f.read()
        except OSError:
            continue  # ended between listdir and open
        fields = text[text.rindex(")") + 2:].split()  # fields from 3 (state) on: index = field - 3
        stats[int(name)] = (int(fields[1]), [int(fields[i]) for i in (11, 12, 13, 14)])
    children = {}
    for pid, (ppid, _) in stats.items():
        children.setdefault(ppid, []).append(pid)
    user = system = 0
    todo = [root]
    while todo:
        pid = todo.pop()
        if pid not in stats:
            continue
        utime, stime, cutime, cstime = stats[pid][1]
        user += utime + cutime
        system += stime + cstime
        todo.extend(children.get(pid, []))
    return user / TICK, system / TICK


def write(path, line):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(line + "\n")
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--prefix", required=True, help="the line's first fields, e.g. 'START COMMIT JOBS'")
    ap.add_argument("--every", type=float, default=30.0)
    ap.add_argument("cmd", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.cmd[1:] if a.cmd[:1] == ["--"] else a.cmd
    if not cmd:
        ap.error("no command after --")
    t0 = time.monotonic()
    child = subprocess.Popen(cmd)
    last = (0.0, 0.0)  # the last heartbeat's tree CPU

    def pass_on(signum, _frame):
        child.send_signal(signum)

    signal.signal(signal.SIGTERM, pass_on)
    signal.signal(signal.SIGINT, pass_on)
    while True:
        try:
            rc = child.wait(timeout=a.every)
            break
        except subprocess.TimeoutExpired:
            user, system = last = tree_cpu(child.pid)
            write(a.out, "%s %.1f %.2f %.2f stopped" % (a.prefix, time.monotonic() - t0, user, system))
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    # A stopped command may leave grandchildren it never reaped (snakemake ending on SIGTERM while
    # its jobs still run): getrusage then misses their time, and the last heartbeat holds more.
    user, system = max((usage.ru_utime, usage.ru_stime), last, key=sum)
    write(a.out, "%s %.1f %.2f %.2f %s" % (a.prefix, time.monotonic() - t0, user, system,
                                            "complete" if rc == 0 else "stopped"))
    return rc


if __name__ == "__main__":
    sys.exit(main())
