#!/usr/bin/env python3
"""Carry a regeneration of every report (scripts/regenerate-reports.sh) across machine sessions.

The full regeneration at the papers' lengths takes ~30 CPU hours, more than a machine session of
this project lasts, and a session's end takes its processes and its disk with it. A checkpoint
keeps what the next session cannot make again cheaply: every run's results (trajectory, run.json,
the cached precision/recall counts, the reuse marker), every sequence's
named small files (synth.yaml, ground truth, frame lists, gt/moving.txt, detection formats), the
seed jobs' reports and `.done` files, the reports and the time log. It leaves out what is large and
made again identically when needed: the sequences' per-frame files and images, which a seed job
synthesises again (same bytes, same commit), and the runs' maps, overlays and traces (listed in
the part as dropped: a run whose table's report reads them, workflow/config.yaml
reports_read_run_files, is made again after a restore until that report is written).

    regen-checkpoint.py save    --work WORK --state DIR [--stop]
    regen-checkpoint.py restore --work WORK --state DIR [--config workflow/config.yaml]

save writes DIR/part-NNN.tar.xz with the files written since the last restore (all files the first
time); --stop first stops a running regeneration (SIGTERM to its heartbeat, whose pid is in
WORK/regenerate.pid: snakemake ends its jobs and the time log gets an exact 'stopped' line).
restore unpacks every part in order into an empty WORK (the same path as the saved one: a run
records its sequence's absolute path, and --collect checks it) and then makes the work folder
consistent for `snakemake --rerun-incomplete`: a sequence without its images is removed (its seed
job synthesises it again and reuses its runs) except where a finished seed job of an image-pruned
table (workflow/config.yaml prune_images) left it so on purpose, or the table's reports are
already written (WORK/reports, scripts/regenerate-reports.sh); a finished seed job of any other
table loses its `.done`, since its report reads the images (it runs again: synthesis, runs reused).
"""
import argparse
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "workflow"))
from tables import tables_of  # noqa: E402  (the work folders as workflow/Snakefile makes them)

STAMP = ".restored"  # WORK/.restored: files newer than it are this session's
# A run's files a checkpoint leaves out: maps, images and traces (the tables' reports read a run's
# trajectory, run.json and cached counts; the few that read more name it in workflow/config.yaml
# reports_read_run_files, and their runs are made again). A --trace frames trace is ~0.4 KB per
# frame and compresses badly: two thirds of a checkpoint if kept.
RUN_LEFT_OUT = (".ply", ".pcd", ".ot", ".bt", ".pgm", ".png", ".jpg", "trace.dtr")


def fail(msg):
    print("regen-checkpoint: " + msg, file=sys.stderr)
    sys.exit(2)


def sequence_file_kept(below):
    """A file of a sequence folder (its path below seq/<preset>/) that a checkpoint keeps: the
    top-level files (synth.yaml, ground truth, lists, the reuse marker) and the named files of gt/
    and detections/<mode>/ (moving.txt, labels.yaml, index.txt, format.txt, ...), not the per-frame
    ones (named by their timestamp), the images or the scene's PLY files."""
    if len(below) == 1:
        return True
    name = below[-1]
    return (below[0] in ("gt", "detections") and len(below) <= 3 and not name[:1].isdigit()
            and not name.endswith((".png", ".ply")))


def classify(rel):
    """'keep', 'skip' (never saved: logs, the pid, the stamp, a sequence's per-frame files) or
    'drop' (a run's map, image or trace: named in the part's list of dropped files, so that restore
    knows the run lost it)."""
    parts = rel.split(os.sep)
    if parts[0] == "logs" or parts[-1] in ("regenerate.pid", STAMP):
        return "skip"
    # a killed run's or synthesis' staging folder (X.tmp.<pid>, renamed onto X when complete) and locks
    if any(".tmp." in p for p in parts) or parts[-1].endswith(".lock"):
        return "skip"
    if "seq" in parts[:-1]:
        return "keep" if sequence_file_kept(parts[parts.index("seq") + 2:]) else "skip"
    if "runs" in parts[:-1] and parts[-1].endswith(RUN_LEFT_OUT):
        return "drop"
    return "keep"


def alive(pid):
    """The process runs (a zombie has ended: its parent has only not reaped it yet)."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            text = f.read()
    except OSError:
        return False
    return text[text.rindex(")") + 2] != "Z"


def stop(work):
    pid_file = os.path.join(work, "regenerate.pid")
    if not os.path.exists(pid_file):
        return
    pid = int(open(pid_file).read().split()[0])
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    print("regen-checkpoint: stopping the regeneration (heartbeat pid %d)" % pid, file=sys.stderr)
    # Snakemake 7 waits for its running jobs on SIGTERM (measured: still running 10 minutes
    # later), so after 30 s the jobs' processes (the heartbeat's whole process group) get SIGTERM too.
    for i in range(1200):
        if not alive(pid):
            break
        if i == 60:
            os.killpg(os.getpgid(pid), signal.SIGTERM)
        time.sleep(0.5)
    else:
        fail("pid %d did not stop within 10 minutes" % pid)
    time.sleep(1)  # regenerate-reports.sh moves the heartbeat's last line into the time log


def parts_in(state):
    """The checkpoint's parts, in the order they were written."""
    return sorted(p for p in os.listdir(state) if p.startswith("part-") and p.endswith(".tar.xz"))


def save(work, state, stop_first):
    if not os.path.isdir(work):
        fail("%s: no work folder" % work)
    if stop_first:
        stop(work)
    stamp = os.path.join(work, STAMP)
    since = os.path.getmtime(stamp) if os.path.exists(stamp) else None
    files, dropped = [], []
    for root, dirs, names in os.walk(work):
        dirs.sort()
        for name in sorted(names):
            path = os.path.join(root, name)
            rel = os.path.relpath(path, work)
            if os.path.islink(path) or not (since is None or os.path.getmtime(path) > since):
                continue
            kind = classify(rel)
            if kind == "keep":
                files.append(rel)
            elif kind == "drop":
                dropped.append(rel)
    os.makedirs(state, exist_ok=True)
    parts = parts_in(state)
    name = "part-%03d.tar.xz" % (len(parts) + 1)
    if not files:
        print("regen-checkpoint: nothing new in %s" % work, file=sys.stderr)
        return
    # The list of the run files left out travels in the part (restore: runs that must be made
    # again when their table's report reads them).
    listing_name = ".checkpoint-dropped-%03d.txt" % (len(parts) + 1)
    with open(os.path.join(work, listing_name), "w") as f:
        f.write("".join(d + "\n" for d in dropped))
    files.append(listing_name)
    tmp = os.path.join(state, name + ".tmp")
    listing = "\n".join(files) + "\n"
    subprocess.run(["tar", "-C", work, "--sort=name", "--owner=0", "--group=0", "--numeric-owner",
                    "-cJf", tmp, "--verbatim-files-from", "-T", "-"], input=listing.encode(), check=True)
    os.replace(tmp, os.path.join(state, name))
    os.remove(os.path.join(work, listing_name))
    print("regen-checkpoint: %s/%s: %d files, %.1f MB (%d run files left out)" % (
        state, name, len(files), os.path.getsize(os.path.join(state, name)) / 1e6, len(dropped)), file=sys.stderr)


def work_folders(config, work):
    """Work folders whose seed jobs prune their sequences' images (as workflow/Snakefile decides),
    and those whose every report this regeneration has written (WORK/reports/<table>.md)."""
    import yaml  # python3-yaml, a dependency of snakemake

    c = yaml.safe_load(open(config))
    prune = set(c.get("prune_images", []))
    folders = tables_of(c["tables"])
    pruned = {w for w, ts in folders.items() if ts[0] in prune}
    reported = {w for w, ts in folders.items()
                if all(os.path.exists(os.path.join(work, "reports", t + ".md")) for t in ts)}
    # work folder -> the endings of the run files its report reads
    reads = c.get("reports_read_run_files", {})
    reads_runs = {w: tuple(e for t in ts for e in reads.get(t, [])) for w, ts in folders.items()}
    return pruned, reported, {w: e for w, e in reads_runs.items() if e}


def restore(work, state, config):
    parts = parts_in(state)
    if not parts:
        fail("%s: no part-NNN.tar.xz" % state)
    if os.path.exists(work) and os.listdir(work):
        fail("%s is not empty: restore unpacks into an empty work folder" % work)
    os.makedirs(work, exist_ok=True)
    for p in parts:
        subprocess.run(["tar", "-C", work, "-xJf", os.path.join(state, p)], check=True)
    pruned, reported, reads_runs = work_folders(config, work)
    # Runs whose report reads a file the checkpoints left out are made again: their reuse marker goes.
    remade = 0
    for listing in sorted(n for n in os.listdir(work) if n.startswith(".checkpoint-dropped-")):
        for rel in open(os.path.join(work, listing)).read().split():
            table = rel.split(os.sep)[0]
            marker = os.path.join(work, os.path.dirname(rel), ".dynref-reproduce")
            if rel.endswith(reads_runs.get(table, ())) and table not in reported and os.path.exists(marker):
                os.remove(marker)
                remade += 1
    removed_seq = undone = 0
    for table in sorted(os.listdir(work)):
        tdir = os.path.join(work, table)
        if not os.path.isdir(tdir) or table == "logs":
            continue
        for seed in sorted(os.listdir(tdir)):
            sdir = os.path.join(tdir, seed)
            if not (seed.startswith("seed") and os.path.isdir(sdir)):
                continue
            done = sdir + ".done"
            # finished and not needing its images again: a pruned table's seed, or any seed of a
            # table whose reports are all written (snakemake runs none of its jobs again)
            finished = os.path.exists(done)
            keep = finished and (table in pruned or table in reported)
            if finished and not keep:
                os.remove(done)
                undone += 1
            for root, dirs, _ in os.walk(sdir):
                dirs.sort()
                if os.path.basename(os.path.dirname(root)) == "seq" and os.path.exists(os.path.join(root, "synth.yaml")):
                    dirs[:] = []
                    if not keep and not os.path.isdir(os.path.join(root, "rgb")):
                        shutil.rmtree(root)
                        removed_seq += 1
    with open(os.path.join(work, STAMP), "w") as f:
        f.write("restored from %s (%d parts)\n" % (state, len(parts)))
    time.sleep(1.1)  # this session's files are newer than the stamp on second-resolution file systems
    print("regen-checkpoint: %s restored from %d parts; %d sequences to synthesise again, %d seed jobs to run"
          " again (their reports read images), %d runs to make again (their reports read maps or full traces)"
          % (work, len(parts), removed_seq, undone, remade), file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("action", choices=["save", "restore"])
    ap.add_argument("--work", required=True)
    ap.add_argument("--state", required=True, help="folder of part-NNN.tar.xz")
    ap.add_argument("--stop", action="store_true", help="save: stop a running regeneration first")
    ap.add_argument("--config", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                                     "workflow", "config.yaml"))
    a = ap.parse_args()
    if a.action == "save":
        save(a.work, a.state, a.stop)
    else:
        restore(a.work, a.state, a.config)


if __name__ == "__main__":
    main()
