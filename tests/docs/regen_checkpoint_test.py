#!/usr/bin/env python3
"""scripts/regen-checkpoint.py on a made-up work folder: what a checkpoint holds, what restore
removes so that snakemake runs again exactly what needs the images, and save --stop.
(tests/reproduce/workflow_test.cpp runs a real regeneration through a checkpoint.)"""
import os
import subprocess
import sys
import tarfile
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import verdict  # noqa: E402

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "regen-checkpoint.py")
CONFIG = """tables: [pruned-t, images-t, reported-t, maps-t, sgdo-table1, sgdo-table2]
prune_images: [pruned-t, sgdo-table1]
reports_read_run_files: {maps-t: [.pcd], reported-t: [.pcd]}
"""


def touch(root, rel, text="x"):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def seq(root, table_seed, rgb=True):
    base = table_seed + "/seq/walking_xyz/"
    for rel in ("synth.yaml", "groundtruth.txt", "gt/moving.txt", "detections/yolo-like/index.txt"):
        touch(root, base + rel)
    if rgb:  # every per-frame file and image of a sequence
        for rel in ("rgb/1.png", "depth/1.png", "gt/motion/1.png", "gt/1700000000.1.png", "gt/1700000000.1.txt",
                    "gt/static_scene.ply", "detections/yolo-like/1700000000.1.txt"):
            touch(root, base + rel)


def run(args):
    return subprocess.run([sys.executable, SCRIPT] + args, capture_output=True, text=True)


def main():
    d = tempfile.mkdtemp()
    config = os.path.join(d, "config.yaml")
    touch(d, "config.yaml", CONFIG)
    w = os.path.join(d, "work")
    # pruned-t: seed 1 finished and pruned, seed 2 running when the session ended
    touch(w, "pruned-t/seed1.done", "")
    seq(w, "pruned-t/seed1", rgb=False)
    seq(w, "pruned-t/seed2")
    # images-t: seed 1 finished (images kept: its report reads them), report not written yet
    touch(w, "images-t/seed1.done", "")
    seq(w, "images-t/seed1")
    touch(w, "images-t/seed1/runs/walking_xyz/mgd/trajectory.txt")
    touch(w, "images-t/seed1/runs/walking_xyz/mgd/trace.dtr")
    touch(w, "images-t/seed1/runs/walking_xyz/epi.tmp.42/run.json")  # a killed run's staging folder
    touch(w, "images-t/seed1/runs/walking_xyz/mgd/.dynref-reproduce")
    # maps-t: its report reads the runs' maps; one run has a map, one has none
    touch(w, "maps-t/seed1.done", "")
    seq(w, "maps-t/seed1")
    touch(w, "maps-t/seed1/runs/walking_xyz/semantic/semantic_map.pcd")
    touch(w, "maps-t/seed1/runs/walking_xyz/semantic/.dynref-reproduce")
    touch(w, "maps-t/seed1/runs/walking_xyz/orb/.dynref-reproduce")
    touch(w, "maps-t/seed1/runs/walking_xyz/orb/trace.dtr")  # dropped, but not a file the report reads
    # reported-t: finished and reported
    touch(w, "reported-t/seed1.done", "")
    seq(w, "reported-t/seed1")
    touch(w, "reported-t/seed1/runs/walking_xyz/semantic/semantic_map.pcd")
    touch(w, "reported-t/seed1/runs/walking_xyz/semantic/.dynref-reproduce")
    touch(w, "reports/reported-t.md")
    # sgdo-main (tables 1 and 2, pruned): one report of two written, so not reported
    touch(w, "sgdo-main/seed1.done", "")
    seq(w, "sgdo-main/seed1", rgb=False)
    touch(w, "reports/sgdo-table1.md")
    touch(w, "logs/table/x.log")
    touch(w, "regenerate-time.log", "S C 2 1 1 1 stopped\n")
    state = os.path.join(d, "state")
    checks = []
    r = run(["save", "--work", w, "--state", state])
    checks.append((r.returncode == 0, "save: %s" % r.stderr))
    names = tarfile.open(os.path.join(state, "part-001.tar.xz")).getnames()
    seq_files = sorted(n for n in names if n.startswith("pruned-t/seed2/seq/"))
    checks += [(seq_files == ["pruned-t/seed2/seq/walking_xyz/" + f for f in
                              ("detections/yolo-like/index.txt", "groundtruth.txt", "gt/moving.txt", "synth.yaml")],
                "a sequence keeps only its named small files: %s" % seq_files),
               (not any(n.endswith((".png", ".ply", ".pcd")) for n in names), "no image, no map: %s" % names),
               (not any(n.endswith("trace.dtr") for n in names), "no trace"),
               (not any(".tmp." in n for n in names), "no staging folder of a killed run"),
               (not any(n.startswith("logs") for n in names), "no logs: %s" % names),
               ("images-t/seed1/runs/walking_xyz/mgd/trajectory.txt" in names, "the run's results"),
               ("regenerate-time.log" in names, "the time log")]
    dropped = tarfile.open(os.path.join(state, "part-001.tar.xz")).extractfile(".checkpoint-dropped-001.txt").read().decode().split()
    checks.append((dropped == ["images-t/seed1/runs/walking_xyz/mgd/trace.dtr",
                               "maps-t/seed1/runs/walking_xyz/orb/trace.dtr",
                               "maps-t/seed1/runs/walking_xyz/semantic/semantic_map.pcd",
                               "reported-t/seed1/runs/walking_xyz/semantic/semantic_map.pcd"],
                   "the part lists the run files it left out: %s" % dropped))
    w2 = os.path.join(d, "work2")
    r = run(["restore", "--work", w2, "--state", state, "--config", config])
    checks.append((r.returncode == 0, "restore: %s" % r.stderr))
    e = lambda rel: os.path.exists(os.path.join(w2, rel))
    checks += [(e("pruned-t/seed1.done") and e("pruned-t/seed1/seq/walking_xyz/synth.yaml"),
                "a finished pruned seed keeps its .done and small files (its report reads them)"),
               (not e("pruned-t/seed2/seq/walking_xyz"), "an unfinished seed's sequence without images is removed"),
               (not e("images-t/seed1.done") and not e("images-t/seed1/seq/walking_xyz"),
                "a finished seed of a table that reads images runs again: .done and sequence removed"),
               (e("images-t/seed1/runs/walking_xyz/mgd/trajectory.txt"), "and its runs are kept (reused)"),
               (e("reported-t/seed1.done") and e("reported-t/seed1/seq/walking_xyz/synth.yaml"),
                "a reported table keeps everything"),
               (e("sgdo-main/seed1.done") and e("sgdo-main/seed1/seq/walking_xyz/synth.yaml"),
                "sgdo-main, pruned and finished, keeps its .done though one of its reports is missing"),
               (not e("maps-t/seed1/runs/walking_xyz/semantic/.dynref-reproduce"),
                "a run whose map its unreported table reads is made again (its marker removed)"),
               (e("maps-t/seed1/runs/walking_xyz/orb/.dynref-reproduce"),
                "a run that lost only files its table's report does not read is reused"),
               (e("images-t/seed1/runs/walking_xyz/mgd/.dynref-reproduce"),
                "a run whose table reads no run files is reused though its full trace is gone"),
               (e("reported-t/seed1/runs/walking_xyz/semantic/.dynref-reproduce"),
                "a reported table's runs are kept as they are")]
    # Nothing new since the restore: no part; then one new file: a part with it alone.
    r = run(["save", "--work", w2, "--state", state])
    checks.append((not os.path.exists(os.path.join(state, "part-002.tar.xz")), "nothing new, no part: %s" % r.stderr))
    touch(w2, "pruned-t/seed2.done", "")
    run(["save", "--work", w2, "--state", state])
    names = tarfile.open(os.path.join(state, "part-002.tar.xz")).getnames()
    checks.append((sorted(names) == [".checkpoint-dropped-002.txt", "pruned-t/seed2.done"],
                   "the second part holds only the new file (and its empty dropped list): %s" % names))
    # --stop: SIGTERM to the pid in regenerate.pid, and save waits for it to end.
    p = subprocess.Popen([sys.executable, "-c", "import time\nwhile True: time.sleep(0.1)"])
    touch(w2, "regenerate.pid", "%d\n" % p.pid)
    t0 = time.monotonic()
    r = run(["save", "--stop", "--work", w2, "--state", state])
    checks += [(p.poll() is not None, "save --stop ended the regeneration: %s" % r.stderr),
               (r.returncode == 0 and time.monotonic() - t0 < 30, "and saved")]
    r = run(["restore", "--work", w2, "--state", state, "--config", config])
    checks.append((r.returncode == 2 and "not empty" in r.stderr, "restore refuses a folder that is not empty"))
    return verdict(checks)


if __name__ == "__main__":
    sys.exit(main())
