#!/usr/bin/env python3
"""A README quotes a result only from the file that holds it (issue 38, item 4).

Every README.md under version control (reports/ aside) is cut into blocks: a paragraph, a list
item, a table row. Code blocks and inline code are left out. Then:
  - a block that links a report (reports/*.md; a link or a path in inline code), or that states
    a result and names the file it comes from (a report, a test, a golden), must find each of its
    numbers (decimals such as 0.0094, percentages such as 40 %) in the text of those files;
  - a block that states a result (ATE, RMSE, RPE, precision, recall, F1, ms/frame) with numbers
    and links no file fails.
Blocks listed in the allow file (its first 60 characters, whitespace collapsed) are known debts:
quoted before this rule, waiting for the regenerated reports; a listed block that changes, or
that no longer exists, fails too, so the list only shrinks.

  python3 scripts/check-readme-numbers.py [--root DIR] [--allow FILE]     exit 0 ok, 1 findings
"""
import argparse
import os
import re
import subprocess
import sys

LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")
CODE_PATH = re.compile(r"`([\w./-]+\.(?:md|cpp|h|txt|csv|json|yaml))`")  # a file named in inline code
NUMBER = re.compile(r"(?<![\w.])(\d+\.\d+|\d+(?= ?%))(?![\w.])")
RESULT = re.compile(r"\b(ATE|RMSE|RPE|precision|recall|F1|ms/frame|ms per frame)\b", re.I)
FENCE = re.compile(r"```.*?```", re.S)


def readmes(root):
    """README.md files under version control (a plain folder: every one), reports/ and the
    checker's own test fixtures aside."""
    git = subprocess.run(["git", "-C", root, "ls-files", "README.md", "*/README.md"], capture_output=True, text=True)
    if git.returncode == 0 and git.stdout.strip():
        files = git.stdout.split()
    else:
        files = [os.path.relpath(os.path.join(d, "README.md"), root)
                 for d, _, names in os.walk(root) if "README.md" in names]
    return sorted(f for f in files if not f.startswith(("reports/", "tests/docs/fixtures/")))


def blocks(text):
    """(first line number, text) of every paragraph, list item and table row; headings end blocks."""
    text = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    cur, start = [], 1
    for i, line in enumerate(text.split("\n"), 1):
        item = line.startswith("|") or re.match(r"\s*([-*]|\d+\.) ", line)
        if not line.strip() or line.startswith("#") or item:
            if cur:
                yield start, "\n".join(cur)
            cur, start = ([line], i) if item else ([], i + 1)
        else:
            if not cur:
                start = i
            cur.append(line)
    if cur:
        yield start, "\n".join(cur)


def key(block):
    return " ".join(block.split())[:60]


def numbers(block):
    """The numbers a block quotes: link targets and inline code aside."""
    prose = re.sub(r"\]\([^)]*\)|`[^`]*`", "", block)
    return NUMBER.findall(prose)


def check(root, allow):
    findings, used = [], set()
    for f in readmes(root):
        with open(os.path.join(root, f), encoding="utf-8") as fh:
            text = fh.read()
        for line, block in blocks(text):
            nums = numbers(block)
            if not nums:
                continue
            targets = []
            for link in LINK.findall(block):
                if re.match(r"[a-z]+:", link):
                    continue  # a URL
                path = os.path.normpath(os.path.join(root, os.path.dirname(f), link))
                if os.path.isfile(path):
                    targets.append(path)
            for named in CODE_PATH.findall(block):  # `reports/x.md`, `tests/eval/figures_test.cpp`
                for base in (root, os.path.join(root, os.path.dirname(f))):
                    if os.path.isfile(os.path.join(base, named)):
                        targets.append(os.path.join(base, named))
                        break
            cites_report = any(os.path.relpath(p, root).startswith("reports" + os.sep) for p in targets)
            if targets and (cites_report or RESULT.search(block)):
                held = ""
                for p in targets:
                    with open(p, encoding="utf-8", errors="replace") as fh:
                        held += fh.read()
                missing = [n for n in nums if n not in held]
                problem = "numbers not in the linked file(s): " + ", ".join(missing) if missing else None
            elif RESULT.search(block):
                problem = "states a result (%s) without linking the report that holds it" % ", ".join(nums[:6])
            else:
                problem = None
            if problem is None:
                continue
            k = f + ": " + key(block)
            if k in allow:
                used.add(k)
                continue
            findings.append((k, "%s:%d: %s" % (f, line, problem)))
    for k in sorted(set(allow) - used):
        findings.append((k, "allow list: '%s' no longer fails as listed (fixed or edited): remove the line" % k))
    return findings


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--allow", default=None, help="default: ROOT/tests/docs/readme_numbers_allow.txt")
    ap.add_argument("--write-allow", action="store_true", help="write today's findings as the allow list")
    a = ap.parse_args()
    allow_path = a.allow or os.path.join(a.root, "tests/docs/readme_numbers_allow.txt")
    allow = []
    if os.path.exists(allow_path) and not a.write_allow:
        with open(allow_path, encoding="utf-8") as fh:
            allow = [l.rstrip("\n") for l in fh if l.strip() and not l.startswith("#")]
    if a.write_allow:
        with open(allow_path, "w", encoding="utf-8") as fh:
            fh.write("# README blocks that quote numbers without the file that holds them (issue 38): known\n"
                     "# debts, to be replaced by links to the regenerated reports. Written by\n"
                     "# scripts/check-readme-numbers.py --write-allow; the list may only shrink.\n")
            fh.write("".join(k + "\n" for k, _ in check(a.root, [])))
        return 0
    findings = check(a.root, allow)
    for _, message in findings:
        print(message)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
