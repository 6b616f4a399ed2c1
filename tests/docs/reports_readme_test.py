#!/usr/bin/env python3
"""scripts/reports_readme.py: reports/README.md names the regeneration's commit, sums the CPU and
wall time of resumed invocations, and fails when a table report names another commit or +dirty."""
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import verdict  # noqa: E402

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "reports_readme.py")
CONFIG = """headline_tables: [t1]
headline_frames: 0
headline_seeds: [1, 2, 3, 4, 5]
ablation_frames: 300
ablation_seeds: [1, 2, 3]
tables: [t1, t2]
"""


def run(reports, log_lines):
    d = tempfile.mkdtemp()
    os.makedirs(d + "/reports")
    for name, text in reports.items():
        open(d + "/reports/" + name, "w").write(text)
    open(d + "/config.yaml", "w").write(CONFIG)
    open(d + "/time.log", "w").write("".join(l + "\n" for l in log_lines))
    p = subprocess.run([sys.executable, SCRIPT, "--time-log", d + "/time.log", "--config", d + "/config.yaml",
                        "--out", d + "/reports/README.md"], capture_output=True, text=True)
    readme = open(d + "/reports/README.md").read() if os.path.exists(d + "/reports/README.md") else ""
    return p.returncode, readme, p.stderr


def main():
    ok = {"t1.md": "Written by dynref (dynref 0.1.0, commit abc123def456).\n",
          "t2.md": "Written (dynref 0.1.0 (abc123def456)).\n", "bench.md": "at dynref 0123456789ab\n"}
    code, readme, err = run(ok, ["2026-11-28T01:00Z abc123def456 2 100 150 10 stopped",
                                 "2026-11-29T01:00Z abc123def456 2 50 60 5 complete"])
    checks = [
        (code == 0, "exit 0 when every table names the commit: " + err),
        ("**abc123def456**" in readme, "names the commit"),
        ("**150 s wall, 225 s CPU**" in readme, "sums wall and CPU over the two invocations"),
        ("summed over 2 invocations" in readme, "says the run was resumed"),
        ("1 of them were stopped before the end" in readme, "says one was stopped before the end"),
        ("| [t1](t1.md) | headline | papers' lengths (preset defaults) | 1,2,3,4,5 | abc123def456 |" in readme, "t1 row"),
        ("| [t2](t2.md) | ablation | 300 | 1,2,3 | abc123def456 |" in readme, "t2 row"),
        ("| [bench.md](bench.md) | 0123456789ab |" in readme, "other reports with their commit"),
    ]
    dirty = dict(ok, **{"t2.md": "Written (dynref 0.1.0 (abc123def456+dirty)).\n"})
    code2, readme2, err2 = run(dirty, ["2026-11-28T01:00Z abc123def456 2 100 150 10"])
    checks += [(code2 == 1, "exit 1 when a table names +dirty"), ("t2 names abc123def456+dirty" in err2, err2)]
    code3, _, err3 = run(ok, ["2026-11-28T01:00Z abc123def456 2 1 1 1", "2026-11-28T02:00Z fff123def456 2 1 1 1"])
    checks += [(code3 != 0 and "several commits" in err3, "refuses a log of two commits: " + err3)]
    return verdict(checks)


if __name__ == "__main__":
    sys.exit(main())
