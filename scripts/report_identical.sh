#!/bin/sh
# Output identity of two shadelab binaries on the report: runs
# `report --scenes scenes --runs 1 --size 64x64` with OLD, with OLD again, and with NEW, then
# compares every output file of NEW with OLD's, apart from run times:
# - JSON: compared value by value, with the timings left out (top-level `timing` and
#   `provenance` (the binary's git revision), any key ending in `_ms`, `_ns`, `_s` or
#   `_per_second`, and `seconds`);
# - PNG (and every other binary file): byte for byte;
# - HTML, Markdown, CSV, SVG, CSS, JS: segment by segment (lines; in HTML and SVG each tag
#   and the text after it), with the git revision masked.
# What a clock measured, and what is decided from it (bench's ratios and speed verdicts, the
# answer's cells under lavapipe's and the software engine's cost models, the charts of
# timings), differs from one run to the next of the same binary. Such a difference is left out
# only where the two runs of OLD differ at the same place too (the same JSON path, the same
# segments of a text file, a binary file that differs between them); everything the two OLD runs
# agree on must be identical in NEW. Prints "identical" and exits 0, or prints every
# difference and exits 1 (2 on a usage error or a run that failed).
#
# Usage: scripts/report_identical.sh OLD_BINARY NEW_BINARY [WORK_DIR]
#        scripts/report_identical.sh --diff-only WORK_DIR  (compare the outputs of an earlier run)
#   WORK_DIR defaults to a fresh temporary folder (kept, and printed, so the outputs can be
#   read afterwards); the runs take about 3 minutes each on 2 cores.
# Example: scripts/report_identical.sh /tmp/shadelab-firstrun target/release/shadelab
set -eu
if [ $# -lt 2 ]; then
    sed -n '2,23p' "$0" >&2
    exit 2
fi
cd "$(dirname "$0")/.."
if [ "$1" = --diff-only ]; then
    work=$2
else
    old=$(realpath "$1")
    new=$(realpath "$2")
    for b in "$old" "$new"; do
        [ -x "$b" ] || {
            echo "$b: not an executable shadelab binary" >&2
            exit 2
        }
    done
    work=${3:-$(mktemp -d "${TMPDIR:-/tmp}/report_identical.XXXXXX")}
    mkdir -p "$work"
    echo "outputs in $work" >&2
    run() { # NAME BINARY
        echo "$1: report ..." >&2
        "$2" report --scenes scenes --runs 1 --size 64x64 --out "$work/$1" \
            >"$work/$1.log" 2>&1 || {
            echo "$1: report failed (see $work/$1.log)" >&2
            exit 2
        }
    }
    rm -rf "$work/old" "$work/old-again" "$work/new"
    run old "$old"
    run new "$new"
    run old-again "$old"
fi

python3 - "$work" <<'EOF'
import json, os, re, subprocess, sys, tempfile

work = sys.argv[1]
OLD, AGAIN, NEW = (os.path.join(work, n) for n in ("old", "old-again", "new"))
for d in (OLD, AGAIN, NEW):
    if not os.path.isfile(os.path.join(d, "index.html")):
        print(f"{d}: no index.html (did the run finish?)")
        sys.exit(2)
TEXT = (".html", ".md", ".csv", ".svg", ".css", ".js", ".txt")


def files(root):
    out = set()
    for r, _, names in os.walk(root):
        for n in names:
            out.add(os.path.relpath(os.path.join(r, n), root))
    return out


def timing_key(k):
    return k.endswith(("_ms", "_ns", "_s", "_per_second")) or k in ("seconds", "timing", "provenance")


def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not timing_key(k)}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x


def json_diff(a, b, path, out):
    """Paths (tuples) where a and b differ."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out.append(path + (k,))
            else:
                json_diff(a[k], b[k], path + (k,), out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(path)
        for i, (x, y) in enumerate(zip(a, b)):
            json_diff(x, y, path + (i,), out)
    elif type(a) != type(b) or a != b:
        # JSON numbers compare exactly: the same bits print the same shortest text.
        out.append(path)


def shown(path):
    return "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in path) or "."


def at(x, path):
    for p in path:
        try:
            x = x[p]
        except (KeyError, IndexError, TypeError):
            return "<none>"
    s = json.dumps(x)
    return s if len(s) < 160 else s[:157] + "..."


REVISION = re.compile(rb"\b[0-9a-f]{12}\b")


def segments(data):
    """A text file as segments: its lines, an HTML or SVG line cut before every tag (one
    segment per element's opening, its text, or its closing)."""
    text = REVISION.sub(b"<revision>", data).decode("utf-8", "replace")
    return [t for t in re.split(r"\n|(?=<)", text) if t.strip()]


def changed(a, b):
    """The blocks (i1, i2, j1, j2) where segment lists `a` and `b` differ ([i1, i2) of `a`
    replaced by [j1, j2) of `b`), by GNU diff over one segment per line (difflib is quadratic
    on the page's 10^5 segments)."""
    with tempfile.TemporaryDirectory() as d:
        for name, toks in (("a", a), ("b", b)):
            with open(os.path.join(d, name), "w") as f:
                f.write("".join(t + "\n" for t in toks))
        out = subprocess.run(["diff", os.path.join(d, "a"), os.path.join(d, "b")],
                             capture_output=True, text=True).stdout
    blocks = []
    for line in out.splitlines():
        m = re.match(r"(\d+)(?:,(\d+))?([acd])(\d+)(?:,(\d+))?$", line)
        if not m:
            continue
        a1, a2, op, b1, b2 = m.groups()
        a1, b1 = int(a1), int(b1)
        a2, b2 = int(a2 or a1), int(b2 or b1)
        if op == "a":  # after line a1 of a: nothing of a replaced
            blocks.append((a1, a1, b1 - 1, b2))
        elif op == "d":  # lines a1..a2 of a gone, after line b1 of b
            blocks.append((a1 - 1, a2, b1, b1))
        else:
            blocks.append((a1 - 1, a2, b1 - 1, b2))
    return blocks


def indices(blocks):
    """The segments of `a` a list of blocks touches (an insertion: the one before it)."""
    out = set()
    for i1, i2, _, _ in blocks:
        out.update(range(i1, i2) if i2 > i1 else (max(i1 - 1, 0), i1))
    return out


problems, masked = [], 0
fo, fa, fn = files(OLD), files(AGAIN), files(NEW)
for rel in sorted((fo | fn) - (fo & fn)):
    if rel in fo and rel not in fa:
        continue  # not even the two OLD runs agree that it exists
    problems.append(f"{rel}: only in {'OLD' if rel in fo else 'NEW'}")
for rel in sorted(fo & fn):
    po, pa, pn = (os.path.join(d, rel) for d in (OLD, AGAIN, NEW))
    again = os.path.exists(pa)
    if rel.endswith(".json"):
        o, n = strip(json.load(open(po))), strip(json.load(open(pn)))
        noisy = []
        if again:
            json_diff(o, strip(json.load(open(pa))), (), noisy)
        diffs = []
        json_diff(o, n, (), diffs)
        for d in diffs:
            if any(q[: len(d)] == d or d[: len(q)] == q for q in noisy):
                masked += 1
            else:
                problems.append(f"{rel}: {shown(d)}: OLD {at(o, d)}, NEW {at(n, d)}")
        continue
    bo, bn = open(po, "rb").read(), open(pn, "rb").read()
    if not rel.endswith(TEXT):
        if bo != bn:
            if again and open(pa, "rb").read() != bo:
                masked += 1
            else:
                problems.append(f"{rel}: differs (byte for byte)")
        continue
    to, tn = segments(bo), segments(bn)
    if to == tn:
        continue
    noisy = indices(changed(to, segments(open(pa, "rb").read()))) if again else set()
    for i1, i2, j1, j2 in changed(to, tn):
        if indices([(i1, i2, j1, j2)]) <= noisy:
            masked += 1
            continue
        problems.append(
            f"{rel}: segment {i1}: OLD {' '.join(to[i1:i2])[:160]!r}, NEW {' '.join(tn[j1:j2])[:160]!r}"
        )
if problems:
    print("\n".join(problems))
    print(f"{len(problems)} differences in {len(fo | fn)} files ({masked} left out as run times)")
    sys.exit(1)
print(f"identical: {len(fo & fn)} files ({masked} differences left out as run times: the two "
      "runs of OLD differ there too)")
EOF
