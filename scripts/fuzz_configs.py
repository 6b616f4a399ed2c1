#!/usr/bin/env python3
"""Config-mutation fuzzing (issue 37): every configs/*.yaml, one parameter value changed per
mutant, each mutant run by `dynref run` on a 2-frame synthetic sequence with a time limit.

A mutant passes when the run exits 0 with complete outputs (run.json end state complete or
lost-at-end, trajectory.txt) and the value was not a non-finite or 1e308 value (those are
refused unless the parameter declares +inf as "no limit"), or exits 2 with a message naming the
mutated file, the mutated line and the key. Anything else is a finding: a crash (signal or exit
code other than 0/2), a hang (over the time limit), an accepted non-finite value, or a refusal
that cites another line or no key.

Mutations are line based (every parameter of a config is one line `key: {value: V, source: ...}`),
so the expected line is the mutated line. Values per parameter kind:
  number: inf, -inf, nan, 1e308, -1, 0, 1.5x, 1e-308, abc, [1, 2], "" (empty)
  bool:   maybe, 1, [true], ""
  list:   [], [no_such_class], person (a scalar), [1, 2]
  text:   bogus_value, "", [a, b]
Every value for the first config that has a (stage, key); `--rotate N` values (rotating through
the list) for each further config with the same key.

The sequences are synthesised once (walking_xyz, 2 frames, ideal detections, `dynref synth --width
W` for each W of `--widths`, default 160,320,640: W x 3W/4 with scaled intrinsics) and shared by
every mutant; each config uses the smallest W on which its unmutated run ends complete (a method
that masks the people needs 320 to initialise), so a mutant costs about one process start plus two
small frames, not a full-size enhancement or dense map.

usage: fuzz_configs.py --dynref BIN --work DIR [--jobs 2] [--timeout 30] [--rotate 1]
                       [--widths 160,320,640] [--limit N] [--table OUT]
"""
import argparse
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
import time

LINE = re.compile(r'^(\s*)([A-Za-z0-9_]+): \{value: (.*), source: (".*")\}\s*$')
NUMBER = re.compile(r'^-?[0-9.]+(e[-+]?[0-9]+)?$')
NON_FINITE = {"inf", "-inf", "nan", "1e308"}
# Accepted values reviewed in the report (no parameter may take them blindly; each accepted one
# is listed with its key so the declared range can be checked by eye).
SUSPECT = {"-1", "0", "1e-308"}
START = time.time()


def kind_of(value):
    if value.startswith("["):
        return "list"
    if value in ("true", "false"):
        return "bool"
    if NUMBER.match(value):
        return "number"
    return "text"


def values_for(kind, value):
    if kind == "number":
        x = float(value)
        scaled = repr(x * 1.5) if "." in value or "e" in value else str(int(round(x * 1.5)))
        return ["inf", "-inf", "nan", "1e308", "-1", "0", scaled, "1e-308", "abc", "[1, 2]", '""']
    if kind == "bool":
        return ["maybe", "1", "[true]", '""']
    if kind == "list":
        return ["[]", "[no_such_class]", "person", "[1, 2]"]
    return ["bogus_value", '""', "[a, b]"]


def mutants(config_dir, rotate):
    """(config name, line number, stage, key, original, mutated value, text)."""
    seen = {}
    out = []
    for name in sorted(os.listdir(config_dir)):
        if not name.endswith(".yaml"):
            continue
        lines = open(os.path.join(config_dir, name)).read().split("\n")
        stage = "backbone"
        for i, line in enumerate(lines):
            m_stage = re.match(r"^\s*- name: (\S+)", line)
            if m_stage:
                stage = m_stage.group(1)
                continue
            if re.match(r"^backbone:", line):
                stage = "backbone"
            m = LINE.match(line)
            if not m:
                continue
            indent, key, value, source = m.groups()
            choices = values_for(kind_of(value), value)
            count = seen.get((stage, key), 0)
            seen[(stage, key)] = count + 1
            if count > 0:  # a key already fuzzed in full: rotate through its values
                start = (count * rotate) % len(choices)
                choices = [choices[(start + j) % len(choices)] for j in range(min(rotate, len(choices)))]
            for v in choices:
                text = list(lines)
                text[i] = "%s%s: {value: %s, source: %s}" % (indent, key, v, source)
                out.append((name, i + 1, stage, key, value, v, "\n".join(text)))
    return out


def run_json(run_dir):
    try:
        return json.load(open(os.path.join(run_dir, "run.json")))
    except (OSError, ValueError):
        return {}


def complete_outputs(run_dir, every_frame=False):
    run = run_json(run_dir)
    if every_frame and run.get("frames_lost", 1) != 0:
        return False
    return run.get("end_state", "") in ("complete", "lost-at-end") and os.path.exists(os.path.join(run_dir, "trajectory.txt"))


def never_initialised(run_dir):
    """A valid config that found too few points on the tiny sequence: the run failed after its
    first frame (exit 2, published nothing over an earlier run), not a refusal of the config."""
    return any(run_json(d).get("end_state", "").startswith("never-initialised") for d in (run_dir, run_dir + ".failed"))


def sequence(args, width):
    """The shared 2-frame sequence of this width (made once) and its ideal detections folder."""
    seq = os.path.join(args.work, "seq%d" % width)
    if not os.path.exists(os.path.join(seq, "rgb.txt")):
        subprocess.run([args.dynref, "synth", "--preset", "walking_xyz", "--frames", "2", "--seed", "1",
                        "--detections", "ideal", "--width", str(width), "--out", seq], check=True, capture_output=True)
    return seq, os.path.join(seq, "detections", "ideal")


def smallest_width(args, config):
    """The smallest of --widths on which the unmutated config tracks every frame (else the largest)."""
    widths = [int(w) for w in args.widths.split(",")]
    for w in widths:
        seq, det = sequence(args, w)
        out = os.path.join(args.work, "base_%s_%d" % (os.path.basename(config), w))
        p = subprocess.run([args.dynref, "run", "--sequence", seq, "--config", config, "--out", out, "--trace", "off",
                            "--no-progress", "--detections", det], capture_output=True, timeout=300)
        if p.returncode == 0 and complete_outputs(out, every_frame=True):
            return w
    return widths[-1]


def run_one(args, seqs, index, m):
    name, line, stage, key, original, value, text = m
    seq, det = seqs[name]
    if args.budget and time.time() - START > args.budget:
        return "not-run", "", 0.0
    wdir = os.path.join(args.work, "m%05d" % index)
    os.makedirs(wdir, exist_ok=True)
    cfg = os.path.join(wdir, name)
    open(cfg, "w").write(text)
    out = os.path.join(wdir, "run")
    cmd = [args.dynref, "run", "--sequence", seq, "--config", cfg, "--out", out, "--trace", "off",
           "--no-progress", "--detections", det]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout, errors="replace")
        code, err = p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        code, err = "hang", ""
    seconds = time.time() - t0
    label = "%s:%d %s.%s=%s (was %s)" % (name, line, stage, key, value, original)
    if code == "hang":
        verdict = "hang"
    elif code == 0:
        verdict = "accepted"
        if not complete_outputs(out):
            verdict = "incomplete"
        elif value in NON_FINITE:
            verdict = "accepted-nonfinite"
        elif value in SUSPECT:
            label += " (accepted)"
    elif code == 2:
        first = err.strip().split("\n")[-1] if err.strip() else ""
        label += " -> " + first[:300]
        where = "%s:%d:" % (cfg, line)
        key_named = ("%s.%s" % (stage, key)) in err
        verdict = "refused" if (where in err and key_named) else "wrong-message"
        if verdict == "wrong-message" and never_initialised(out):
            verdict = "not-initialised"
    else:
        verdict = "crash"
        label += " -> exit %s: %s" % (code, err.strip()[-300:])
    if verdict in ("accepted", "refused", "not-initialised"):
        shutil.rmtree(wdir, ignore_errors=True)
    return verdict, label, seconds


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dynref", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--configs", default="configs")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=30)
    ap.add_argument("--rotate", type=int, default=1)
    ap.add_argument("--limit", type=int, default=0, help="first N mutants only (0 = all)")
    ap.add_argument("--table", default="-")
    ap.add_argument("--widths", default="160,320,640", help="image widths tried per config, smallest first")
    ap.add_argument("--budget", type=float, default=0, help="stop starting mutants after this many seconds (0 = none)")
    ap.add_argument("--fresh", action="store_true", help="empty --work first (a new sequence)")
    args = ap.parse_args()
    if args.fresh:
        shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work, exist_ok=True)
    ms = mutants(args.configs, args.rotate)
    # Round robin over the configs (a time budget then covers every config), then every 7th
    # mutant of a config first (spread over its parameters and values).
    rank, order = {}, []
    for m in ms:
        k = rank.get(m[0], 0)
        rank[m[0]] = k + 1
        order.append(((k * 7) % 11, k, m[0]))
    ms = [m for _, m in sorted(zip(order, ms), key=lambda t: t[0])]
    if args.limit:
        ms = ms[: args.limit]
    widths = {}
    for name in sorted({m[0] for m in ms}):
        widths[name] = smallest_width(args, os.path.join(args.configs, name))
        print("%s: %d px" % (name, widths[name]), file=sys.stderr, flush=True)
    seqs = {name: sequence(args, w) for name, w in widths.items()}
    counts = {}
    findings, examples, suspects, seconds = [], {}, [], []
    per_config = {}
    log = open(os.path.join(args.work, "results.jsonl"), "w")
    t0 = time.time()
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = [pool.submit(run_one, args, seqs, i, m) for i, m in enumerate(ms)]
        for i, f in enumerate(futures):
            verdict, label, sec = f.result()
            counts[verdict] = counts.get(verdict, 0) + 1
            log.write(json.dumps({"verdict": verdict, "label": label, "seconds": round(sec, 3)}) + "\n")
            if verdict != "not-run":
                seconds.append(sec)
            if verdict in ("accepted", "refused") and len(examples.setdefault(verdict, [])) < 4 and ms[i][5] in NON_FINITE | SUSPECT | {"abc", "[1, 2]"}:
                examples[verdict].append(label)
            if verdict == "accepted" and label.endswith("(accepted)"):
                suspects.append(label)
            pc = per_config.setdefault(ms[i][0], {})
            pc[verdict] = pc.get(verdict, 0) + 1
            if verdict == "not-initialised":
                suspects.append("not initialised: " + label)
            elif verdict not in ("accepted", "refused", "not-run"):
                findings.append("%s: %s" % (verdict, label))
                print("FINDING %s: %s" % (verdict, label), file=sys.stderr, flush=True)
            if (i + 1) % 100 == 0:
                print("%d/%d mutants, %.0f s" % (i + 1, len(ms), time.time() - t0), file=sys.stderr, flush=True)
    kinds = ["accepted", "refused", "not-initialised", "crash", "hang", "accepted-nonfinite", "incomplete", "wrong-message", "not-run"]
    lines = ["| config | width | mutants | " + " | ".join(kinds) + " |", "|---" * (len(kinds) + 3) + "|"]
    for name in sorted(per_config):
        pc = per_config[name]
        lines.append("| %s | %d | %d | %s |" % (name, widths[name], sum(pc.values()), " | ".join(str(pc.get(k, 0)) for k in kinds)))
    lines.append("| **all** | | **%d** | %s |" % (len(ms), " | ".join("**%d**" % counts.get(k, 0) for k in kinds)))
    lines.append("")
    lines.append("Wall time %.0f s with %d jobs, time limit %g s per mutant; %s." % (
        time.time() - t0, args.jobs, args.timeout,
        "seconds per mutant: median %.2f, max %.2f" % (sorted(seconds)[len(seconds) // 2], max(seconds)) if seconds else "none ran"))
    for verdict in ("accepted", "refused"):
        if examples.get(verdict):
            lines += ["", "Examples, %s:" % verdict, "```"] + examples[verdict] + ["```"]
    if suspects:
        lines += ["", "Accepted -1, 0 or 1e-308, and valid values on which the run did not initialise (%d; listed for review):" % len(suspects),
                  "```"] + suspects + ["```"]
    if findings:
        lines += ["", "Findings:", "```"] + findings + ["```"]
    table = "\n".join(lines) + "\n"
    if args.table == "-":
        sys.stdout.write(table)
    else:
        open(args.table, "w").write(table)
    return 0 if not findings else 1


if __name__ == "__main__":
    sys.exit(main())
