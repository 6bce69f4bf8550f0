#!/bin/sh
# Output identity of two shadelab binaries on the report: runs
# `report --scenes scenes --runs 1 --size 64x64` with OLD, with NEW, and with OLD again (each
# binary copied as `shadelab` into a folder of its own: isa's children re-run it by that
# name), then compares every output file of NEW with OLD's, apart from run times:
# - JSON: value by value, timings left out (top-level `timing` and `provenance` (the binary's
#   git revision), `command_line` (the binary's path), any key ending in `_ms`, `_ns`, `_s` or
#   `_per_second`, and `seconds`);
# - PNG (and every other binary file): byte for byte;
# - HTML, Markdown, CSV, SVG, CSS, JS: segment by segment (lines; in HTML and SVG each tag and
#   the text after it), the git revision masked.
# What a clock measured, and what is decided from it (bench's ratios and speed words, speed
# claims' verdicts, the answer's cells under lavapipe's and the software engine's cost models,
# the charts of timings), differs from one run to the next of the same binary. Such a
# difference is left out only where the runs of OLD differ in the same row too: the same list
# element of a JSON file (a method's row, a claim, a cell), the same row of a text file (a
# table row, list item, paragraph, line), a binary file that differs between them. Everything
# the OLD runs agree on must be identical in NEW: compare's statistics and images, stress,
# plan, the budget checks, every row without a timing. More runs of OLD sharpen what counts
# as timing: any folder WORK_DIR/old-again* is read as one. Prints "identical" and exits 0, or
# prints every difference and exits 1 (2 on a usage error or a run that failed).
#
# Usage: scripts/report_identical.sh OLD_BINARY NEW_BINARY [WORK_DIR]
#        scripts/report_identical.sh --diff-only WORK_DIR  (compare the outputs of an earlier run)
#   WORK_DIR defaults to a fresh temporary folder (kept, and printed, so the outputs can be
#   read afterwards); each run takes about 3 minutes on 2 cores.
# Example: scripts/report_identical.sh /tmp/shadelab-firstrun target/release/shadelab
set -eu
if [ $# -lt 2 ]; then
    sed -n '2,28p' "$0" >&2
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
    # isa's children re-run the binary as `shadelab child`: each binary runs as `shadelab`
    # from a folder of its own (one not named so compiles nothing for the report)
    rm -rf "$work/old" "$work/old-again" "$work/new" "$work/bin"
    mkdir -p "$work/bin/old" "$work/bin/new"
    cp "$old" "$work/bin/old/shadelab"
    cp "$new" "$work/bin/new/shadelab"
    run old "$work/bin/old/shadelab"
    run new "$work/bin/new/shadelab"
    run old-again "$work/bin/old/shadelab"
fi

python3 - "$work" <<'EOF'
import json, os, re, subprocess, sys, tempfile

work = sys.argv[1]
OLD, NEW = os.path.join(work, "old"), os.path.join(work, "new")
# every further run of OLD: old-again, old-again-2, ...
AGAINS = sorted(
    os.path.join(work, n)
    for n in os.listdir(work)
    if n.startswith("old-again") and os.path.isdir(os.path.join(work, n))
)
if not AGAINS:
    print(f"{work}: no old-again run of OLD to tell run times by")
    sys.exit(2)
for d in [OLD, NEW] + AGAINS:
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
    return k.endswith(("_ms", "_ns", "_s", "_per_second")) or k in (
        "seconds",
        "timing",
        "provenance",
        # the binary's path and the output folder, as the command line of a child run
        "command_line",
    )


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


def row_of(path):
    """The row a timing-dependent value belongs to: the list element it lies in (a method's
    row, a claim, a cell, a figure), else the object holding it. Its other fields are decided
    from the same measurement (a speed word, a verdict, a reason)."""
    ints = [i for i, p in enumerate(path) if isinstance(p, int)]
    if ints:
        return path[: ints[-1] + 1]
    return path[:-1] if len(path) > 1 else path


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


def segments(data, markup):
    """A text file as segments: its lines; an HTML or SVG line (`markup`) cut before every
    tag too (one segment per element's opening, its text, or its closing)."""
    text = REVISION.sub(b"<revision>", data).decode("utf-8", "replace")
    return [t for t in re.split(r"\n|(?=<)" if markup else r"\n", text) if t.strip()]


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


# The segments that open a row of a page: what a timing-dependent segment's neighbours in the
# same row are decided from (a table row, a list item, a paragraph, a heading, a figure).
ROW = re.compile(r"<(tr|li|p|h[1-6]|figure|details|summary|section|table|ul|ol)[\s>]")


def rows(segs):
    """Each segment's row: the index of the segment opening it ([`ROW`]; a line of a text
    file without tags is its own row)."""
    out, row = [], 0
    for i, t in enumerate(segs):
        if ROW.match(t) or not t.startswith("<"):
            row = i if ROW.match(t) or "<" not in t else row
        out.append(row)
    return out


def widen(noisy, segs):
    """`noisy` segments widened to their whole rows."""
    r = rows(segs)
    hit = {r[i] for i in noisy if i < len(segs)}
    return {i for i in range(len(segs)) if r[i] in hit} | noisy


problems, masked = [], 0
fo, fn = files(OLD), files(NEW)
fa = [files(a) for a in AGAINS]
for rel in sorted((fo | fn) - (fo & fn)):
    if any((rel in fo) != (rel in f) for f in fa):
        continue  # the OLD runs do not agree that it exists
    problems.append(f"{rel}: only in {'OLD' if rel in fo else 'NEW'}")
for rel in sorted(fo & fn):
    po, pn = os.path.join(OLD, rel), os.path.join(NEW, rel)
    pas = [p for p in (os.path.join(a, rel) for a in AGAINS) if os.path.exists(p)]
    if rel.endswith(".json"):
        o, n = strip(json.load(open(po))), strip(json.load(open(pn)))
        noisy = []
        for pa in pas:
            json_diff(o, strip(json.load(open(pa))), (), noisy)
        noisy = [row_of(q) for q in noisy]
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
            if any(open(pa, "rb").read() != bo for pa in pas):
                masked += 1
            else:
                problems.append(f"{rel}: differs (byte for byte)")
        continue
    markup = rel.endswith((".html", ".svg"))
    to, tn = segments(bo, markup), segments(bn, markup)
    if to == tn:
        continue
    noisy = set()
    for pa in pas:
        noisy |= indices(changed(to, segments(open(pa, "rb").read(), markup)))
    noisy = widen(noisy, to)
    timed = {to[i] for i in noisy}
    for i1, i2, j1, j2 in changed(to, tn):
        # OLD's segments all timing-dependent; or a run of NEW's segments that OLD has among
        # its timing-dependent rows, moved by the diff's alignment across one of them
        moved = i2 == i1 and all(t in timed for t in tn[j1:j2])
        if indices([(i1, i2, j1, j2)]) <= noisy or moved:
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
