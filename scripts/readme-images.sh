#!/usr/bin/env bash
# The README's picture of the overview page (issue 36), from a demo output: `bash scripts/demo.sh`
# first. Renders OUT/overview.md to OUT/overview.html (python3-markdown, its tables extension) and
# photographs its top in Debian's headless Chromium into docs/img/overview_page.png.
# usage: bash scripts/readme-images.sh [OUT (default out/demo)]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/demo}
if [ ! -f "$OUT/overview.md" ]; then
  echo "readme-images: $OUT/overview.md: missing (run bash scripts/demo.sh first)" >&2
  exit 2
fi
# Debian's interpreter, where apt puts python3-markdown (a python3 earlier in PATH may lack it).
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" -c 'import markdown' 2> /dev/null || {
  echo "readme-images: python3-markdown missing (apt-get install python3-markdown)" >&2
  exit 2
}
chromium=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chromium" ] || { echo "readme-images: chromium missing (bash scripts/install-deps.sh --tests)" >&2; exit 2; }

"$py" - "$OUT/overview.md" "$OUT/overview.html" << 'PY'
import sys, markdown
src, dst = sys.argv[1], sys.argv[2]
body = markdown.markdown(open(src, encoding="utf-8").read(), extensions=["tables", "fenced_code"])
style = """body{font:14px/1.45 -apple-system,'Segoe UI',Helvetica,Arial,sans-serif;margin:24px;max-width:1360px;color:#1f2328}
table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #d0d7de;padding:3px 8px;text-align:right}
th{background:#f6f8fa}td:first-child,th:first-child{text-align:left}img{max-width:100%}
code{background:#f6f8fa;padding:1px 4px;border-radius:4px;font-size:90%}"""
with open(dst, "w", encoding="utf-8") as f:
    f.write(f"<!doctype html><meta charset=utf-8><title>dynref overview</title><style>{style}</style>\n{body}\n")
PY

mkdir -p docs/img
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
"$chromium" --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
  --user-data-dir="$profile" --allow-file-access-from-files --window-size=1400,1500 \
  --screenshot="$PWD/docs/img/overview_page.png" "file://$(realpath "$OUT/overview.html")" 2> /dev/null
echo "readme-images: docs/img/overview_page.png from $OUT/overview.md" >&2
