#!/usr/bin/env python3
"""Markdown report of scripts/bench-realtime.sh (issue 35) from its runs' run.json, eval.json and GNU time.

realtime_report.py REPORT VERSION NPROC UPTIME ROW...   ROW = kind|preset|frames|seed|method|run_dir
"""
import json
import os
import re
import statistics
import sys

TARGETS = {"orb": 20.0, "epi_ALL": 50.0, "sgdo": 33.0, "mgd": 33.0, "blur": 33.0, "epi": 33.0, "semantic": 33.0}
MODULES = ["extraction", "lines", "planes", "tracking", "local_mapping", "ba"]


def load(run):
    j = json.load(open(os.path.join(run, "run.json")))
    ev = json.load(open(os.path.join(run, "eval.json")))
    rss = float(re.search(r"Maximum resident set size \(kbytes\): (\d+)", open(run + ".time").read()).group(1)) / 2**20
    return j, ev["ate"]["stats"]["rmse"], rss


def triple(t, key):
    s = t.get(key)
    if not s or "mean_ms_per_frame" not in s:
        return "-"
    p95 = s.get("p95_ms_per_frame")
    return f"{s['mean_ms_per_frame']:.1f} / {s['median_ms_per_frame']:.1f} / {'-' if p95 is None else f'{p95:.1f}'}"


def stages(j):
    st = j.get("timing_stages", {})
    return ", ".join(f"{k} {v:.1f}" for k, v in sorted(st.items())) or "-"


def main():
    report, version, nproc, uptime, rows = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]
    runs = []
    for row in rows:
        kind, preset, frames, seed, method, run = row.split("|")
        j, ate, rss = load(run)
        runs.append(dict(kind=kind, preset=preset, frames=int(frames), seed=seed, method=method, j=j, ate=ate, rss=rss))
    orb = {(r["kind"], r["preset"], r["frames"], r["seed"]): r["j"]["timing"]["slam"]["mean_ms_per_frame"]
           for r in runs if r["method"] == "orb"}

    def ratio(r):
        base = orb.get((r["kind"], r["preset"], r["frames"], r["seed"]))
        return r["j"]["timing"]["slam"]["mean_ms_per_frame"] / base if base else None

    table = [r for r in runs if r["kind"] == "table"]
    long = [r for r in runs if r["kind"] == "long"]
    sizes = sorted({(r["preset"], r["frames"]) for r in table})
    seeds = sorted({r["seed"] for r in table})
    long_sizes = sorted({"%s %d frames seed %s" % (r["preset"], r["frames"], r["seed"]) for r in long})
    out = [
        "# Real time on one core (issues 18, 35)", "",
        f"Written by `scripts/bench-realtime.sh` with {version}: `dynref run --trace off`, one thread, 640x480, "
        f"synthetic sequences with yolo-like detections; table runs: {', '.join(f'{p} {n} frames' for p, n in sizes) or '-'}, "
        f"seeds {' '.join(seeds) or '-'}; long runs: {', '.join(long_sizes) or 'none'}.",
        "", f"Machine: {nproc} cores, shared with other jobs while the bench ran (`uptime` at the end: {uptime.strip()}). "
        "Absolute ms are inflated by that load; **ratio to orb** (the method's slam ms over orb's on the same sequence "
        "in the same bench run) is the number that holds.", "",
        "ms = thread CPU ms per frame from run.json (`slam` = everything but image loading; extraction includes "
        "`before_extraction` stages, lines and planes; tracking includes the method stages; local mapping includes "
        "`on_map_update` stages and map modules). Cells are mean / p50 / p95 over the frames. Stage columns: each method "
        "stage's mean ms per frame. Peak RSS from GNU time. ATE RMSE over the tracked frames (SE(3) alignment).", "",
        "## Per method (mean over the table runs)", "",
        "| method | runs | slam ms | ratio to orb (min-max) | issue 35 target | target met at this size |",
        "|---|---|---|---|---|---|",
    ]
    for m in dict.fromkeys(r["method"] for r in table):
        rs = [r for r in table if r["method"] == m]
        slam = statistics.mean(r["j"]["timing"]["slam"]["mean_ms_per_frame"] for r in rs)
        ratios = [x for x in (ratio(r) for r in rs) if x is not None]
        rtxt = f"{statistics.mean(ratios):.2f} ({min(ratios):.2f}-{max(ratios):.2f})" if ratios else "-"
        target = TARGETS.get(m)
        met = "-" if target is None else ("yes" if slam <= target else "no")
        out.append(f"| {m} | {len(rs)} | {slam:.1f} | {rtxt} | {'-' if target is None else f'<= {target:g} ms'} | {met} |")
    out += ["", "## Table runs", "",
            "| preset | seed | method | slam | ratio to orb | " + " | ".join(m.replace("_", " ") for m in MODULES) +
            " | stages (mean ms) | ATE m | tracked |",
            "|---|---|---|---|---|" + "---|" * len(MODULES) + "---|---|---|"]
    for r in table:
        t, x = r["j"]["timing"], ratio(r)
        out.append(f"| {r['preset']} | {r['seed']} | {r['method']} | {triple(t, 'slam')} | {'-' if x is None else f'{x:.2f}'} | "
                   + " | ".join(triple(t, k) for k in MODULES)
                   + f" | {stages(r['j'])} | {r['ate']:.4f} | {r['j']['frames_tracked']}/{r['j']['frames_processed']} |")
    if long:
        out += ["", "## Long runs: flat in sequence length, memory", "",
                "head / tail = mean slam ms over the first / last 100 frames.", "",
                "| preset | frames | method | slam | ratio to orb | head | tail | tail/head | keyframes | peak RSS GiB | ATE m |",
                "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in long:
            s, x = r["j"]["timing"]["slam"], ratio(r)
            out.append(f"| {r['preset']} | {r['frames']} | {r['method']} | {s['mean_ms_per_frame']:.1f} | "
                       f"{'-' if x is None else f'{x:.2f}'} | {s['head_mean_ms_per_frame']:.1f} | {s['tail_mean_ms_per_frame']:.1f} | "
                       f"{s['tail_mean_ms_per_frame'] / s['head_mean_ms_per_frame']:.2f} | {r['j']['keyframes_created']} | "
                       f"{r['rss']:.2f} | {r['ate']:.4f} |")
    os.makedirs(os.path.dirname(os.path.abspath(report)), exist_ok=True)
    tmp = report + ".tmp"
    open(tmp, "w").write("\n".join(out) + "\n")
    os.replace(tmp, report)
    print("\n".join(out))


if __name__ == "__main__":
    main()
