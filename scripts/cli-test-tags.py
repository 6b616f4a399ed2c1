#!/usr/bin/env python3
"""Every Catch2 TEST_CASE that runs the dynref executable, directly or through a helper defined in its
own file or in a test header, carries the tag [cli]: the sanitizer job (scripts/test-sanitizers.sh)
registers only the untagged unit tests and the [golden] ones (DEVELOPERS.md: "keep the sanitizer
job on unit tests and goldens").
  python3 scripts/cli-test-tags.py           list untagged CLI tests, exit 1 if there is one (a ctest)
  python3 scripts/cli-test-tags.py --write   add the missing tags in place
A TEST_CASE whose name is not one string literal (made by a macro, e.g. verify_configs_test.cpp) is
not seen: tag it by hand."""
import re, sys, pathlib
ROOT = pathlib.Path(__file__).resolve().parent.parent / 'tests'
SEED = {'RunDynref', 'ExpectBadInput', 'DynrefExe'}

def match_brace(s, i):
    depth = 0
    j = i
    in_str = None
    while j < len(s):
        c = s[j]
        if in_str:
            if c == '\\': j += 2; continue
            if c == in_str: in_str = None
        elif s.startswith('//', j):  # a comment's apostrophe ("paper's") is not a char literal
            j = s.find('\n', j)
            if j < 0: return len(s) - 1
            continue
        elif s.startswith('/*', j):
            j = s.find('*/', j) + 2
            if j < 2: return len(s) - 1
            continue
        elif c in '"\'':
            # raw strings R"(...)"
            if c == '"' and j > 0 and s[j-1] == 'R':
                end = s.find(')"', j)
                j = end + 2; continue
            in_str = c
        elif c == '{': depth += 1
        elif c == '}':
            depth -= 1
            if depth == 0: return j
        j += 1
    return len(s) - 1

FUNC = re.compile(r'^[\w:<>,\s\*&]*?\b(\w+)\s*\([^;{}]*\)\s*(?:const\s*)?\{', re.M)
TC = re.compile(r'TEST_CASE\s*\(\s*("(?:[^"\\]|\\.)*")\s*(?:,\s*("(?:[^"\\]|\\.)*"))?\s*\)\s*\{')

def functions(text):
    out = {}
    for m in FUNC.finditer(text):
        name = m.group(1)
        if name in ('if', 'for', 'while', 'switch', 'TEST_CASE', 'SECTION', 'catch'): continue
        b = m.end() - 1
        out.setdefault(name, text[b:match_brace(text, b) + 1])
    return out

def calls(body, names):
    return any(re.search(r'\b' + re.escape(n) + r'\s*\(', body) for n in names)

files = sorted(ROOT.rglob('*.cpp')) + sorted(ROOT.rglob('*.h'))
texts = {f: f.read_text() for f in files}
def closure(funcs, base):
    cli = set(base)
    changed = True
    while changed:
        changed = False
        for n, bodies in funcs.items():
            if n not in cli and any(calls(b, cli) for b in bodies):
                cli.add(n); changed = True
    return cli

shared = {}
for f, t in texts.items():
    if f.suffix == '.h':
        for n, b in functions(t).items():
            shared.setdefault(n, []).append(b)
shared_cli = closure(shared, SEED)
write = '--write' in sys.argv
total = tagged = missing = 0
for f, t in texts.items():
    if f.suffix != '.cpp': continue
    local = {n: [b] for n, b in functions(t).items()}
    cli = closure(local, shared_cli)
    edits = []
    for m in TC.finditer(t):
        total += 1
        b = m.end() - 1
        body = t[b:match_brace(t, b) + 1]
        if not calls(body, cli): continue
        tagged += 1
        tags = m.group(2)
        if tags and '[cli]' in tags: continue
        missing += 1
        if tags:
            new = tags[:-1] + '[cli]"'
            edits.append((m.start(2), m.end(2), new))
        else:
            edits.append((m.end(1), m.end(1), ', "[cli]"'))
        if not write: print(f'tests/{f.relative_to(ROOT)}: {m.group(1)} runs dynref but has no [cli] tag')
    if write and edits:
        for s, e, new in reversed(edits):
            t = t[:s] + new + t[e:]
        f.write_text(t)
print(f'{tagged} of {total} TEST_CASEs run the CLI, {missing} without the [cli] tag', file=sys.stderr)
sys.exit(1 if missing and not write else 0)
