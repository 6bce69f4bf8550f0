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
# difference is left out where it is, by rule, decided from a clock:
# - a row that names a clock-measured cost model (one whose `kind` in OLD's answer.json is
#   "interval": lavapipe's frame time and isolated cost, the software engine): its answer
#   cells, its figures, the per-scene answers that list it, whatever lies in an object that
#   has it as a value (skips' grouping by lavapipe's isolated cost); in a text file, a table
#   row naming its id or title;
# - a clock check (any `clock` object: which clock tracks the draw is itself measured);
# - bench.json's `pareto_front` (the methods on the front of run time against error);
# - a list whose elements are the same in another order, in an object that names a
#   clock-measured cost model (auto's candidates, ordered by lavapipe's isolated cost);
# - the answer's counts and words over every cell (answer.json's `summary.common`,
#   `summary.differing` and `summary.sentences`), which count the clock-measured cells too;
# - a chart (SVG) whose runs of OLD differ: a chart of timings, every label placed by them;
# - prose (a heading, paragraph or list item, not a table row) of a section (HTML <section>,
#   Markdown `# ` heading) with table rows the runs of OLD differ in: its words count them;
# - where a result came from (skips.json's `auto.source`: computed now, or read from the cache
#   that the run before wrote; isa.json's `families[].source` and the page's "Compiled in this
#   run": compiled now or read from the compile store);
# and where the runs of OLD differ in the same row too: the same list element of a JSON file
# (a method's row, a claim), the same row of a text file (a table row, list item, paragraph,
# line), a binary file that differs between them. Everything else must be identical in NEW:
# compare's statistics and images, stress, plan, the budget checks, every static cost and its
# answer cells, every row without a timing. More runs of OLD sharpen what counts as timing:
# any folder WORK_DIR/old-again* is read as one. Prints "identical" and exits 0, or prints
# every difference and exits 1 (2 on a usage error or a run that failed). SHOW_MASKED=1 also
# prints each difference left out, and the rules that left it out.
#
# Usage: scripts/report_identical.sh OLD_BINARY NEW_BINARY [WORK_DIR]
#        scripts/report_identical.sh --diff-only WORK_DIR  (compare the outputs of an earlier run)
#   WORK_DIR defaults to a fresh temporary folder (kept, and printed, so the outputs can be
#   read afterwards); each run takes about 3 minutes on 2 cores.
# Example: scripts/report_identical.sh /tmp/shadelab-firstrun target/release/shadelab
set -eu
if [ $# -lt 2 ]; then
    sed -n '2,46p' "$0" >&2
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

# The clock-measured cost models (kind "interval" in OLD's answer): their ids and titles.
try:
    _models = json.load(open(os.path.join(OLD, "answer.json")))["cost_models"]
except (OSError, KeyError, ValueError) as e:
    print(f"{OLD}/answer.json: no cost models to tell the clock-measured ones by ({e})")
    sys.exit(2)
MEASURED = {m["name"] for m in _models if m.get("kind") == "interval"}
MEASURED_WORDS = sorted(MEASURED | {m["title"] for m in _models if m["name"] in MEASURED})
# answer.json's counts and words over every cell, the clock-measured ones too
AGGREGATES = [("summary", "common"), ("summary", "differing"), ("summary", "sentences")]
# where a result came from, not what it is (a cache the run before wrote, the compile store):
# paths, None standing for any list index
PROVENANCE = [("auto", "source"), ("families", None, "source")]
PROVENANCE_TEXT = re.compile(r"Compiled in this run: \d+ famil")
# decided by run times in a file of measurements: (file name, path)
TIMED = [("bench.json", ("pareto_front",))]


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


def provenance(path):
    return any(
        len(p) == len(path) and all(q is None or q == r for q, r in zip(p, path))
        for p in PROVENANCE
    )


def strip(x, path=()):
    if isinstance(x, dict):
        return {
            k: strip(v, path + (k,))
            for k, v in x.items()
            if not timing_key(k) and not provenance(path + (k,))
        }
    if isinstance(x, list):
        return [strip(v, path + (i,)) for i, v in enumerate(x)]
    return x


def under_measured(x, path):
    """Whether an object on `path` (the file's root down to the value) names a clock-measured
    cost model as one of its own values (skips' grouping by lavapipe's isolated cost), or the
    path runs through a clock check (`clock`: which clock tracks the draw is measured)."""
    for k, p in enumerate(path):
        if p == "clock":
            return True
        v = at_value(x, path[:k])
        if isinstance(v, dict) and any(isinstance(w, str) and w in MEASURED for w in v.values()):
            return True
    return False


def reordered_by_measure(o, n, path):
    """Whether the difference at `path` is only a new order of the list holding it (the same
    elements), in an object that names a clock-measured cost model somewhere inside it (auto's
    candidates, cheapest first by lavapipe's isolated cost)."""
    ints = [i for i, p in enumerate(path) if isinstance(p, int)]
    if not ints:
        return False
    lp = path[: ints[0]]
    lo, ln = at_value(o, lp), at_value(n, lp)
    if not (isinstance(lo, list) and isinstance(ln, list)):
        return False
    key = lambda v: json.dumps(v, sort_keys=True)
    if sorted(map(key, lo)) != sorted(map(key, ln)):
        return False
    return any(names_measured(at_value(o, lp[:k])) for k in range(1, len(lp)))


def names_measured(x):
    """Whether a JSON value names a clock-measured cost model anywhere in it."""
    if isinstance(x, dict):
        return any(names_measured(v) for v in x.values())
    if isinstance(x, list):
        return any(names_measured(v) for v in x)
    return isinstance(x, str) and x in MEASURED


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


def row_of(path, root):
    """The row a timing-dependent value belongs to: the list element it lies in (a method's
    row, a claim, a cell, a figure), else the list itself (one whose length differs), else the
    object holding it. Its other fields are decided from the same measurement (a speed word, a
    verdict, a reason)."""
    ints = [i for i, p in enumerate(path) if isinstance(p, int)]
    if ints:
        return path[: ints[-1] + 1]
    if isinstance(at_value(root, path), list):
        return path
    return path[:-1] if len(path) > 1 else path


MISSING = object()


def at_value(x, path, missing=None):
    """The value at `path` of `x`, or `missing`."""
    for p in path:
        try:
            x = x[p]
        except (KeyError, IndexError, TypeError):
            return missing
    return x


def shown(path):
    return "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in path) or "."


def at(x, path):
    """The value at `path` of `x` as JSON, cut to a line, or `<none>`."""
    v = at_value(x, path, MISSING)
    if v is MISSING:
        return "<none>"
    s = json.dumps(v)
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


def rows(segs, markup):
    """Each segment's row: the index of the segment opening it ([`ROW`]; a line of a text
    file without tags, and every line of a Markdown or CSV file, is its own row)."""
    if not markup:
        return list(range(len(segs)))
    out, row = [], 0
    for i, t in enumerate(segs):
        if ROW.match(t) or not t.startswith("<"):
            row = i if ROW.match(t) or "<" not in t else row
        out.append(row)
    return out


SECTION = re.compile(r"<section[\s>]|# ")
PROSE = re.compile(r"<(li|p|h[1-6]|figcaption|summary)[\s>]")


def sections(segs):
    """Each segment's section: the index of the segment opening it (an HTML <section>, a
    Markdown heading of the first level); 0 before the first."""
    out, sec = [], 0
    for i, t in enumerate(segs):
        if SECTION.match(t):
            sec = i
        out.append(sec)
    return out


def prose(segs, markup):
    """The segments of prose: in a page, those of a row opened by a heading, paragraph or list
    item (not a table row); in Markdown, every line that is not a table row."""
    if not markup:
        return {i for i, t in enumerate(segs) if not t.lstrip().startswith("|")}
    r = rows(segs, markup)
    return {i for i in range(len(segs)) if PROSE.match(segs[r[i]])}


def names_measured_text(segs, idx, words):
    """Whether the table rows (not prose: `words`) of segments `idx` name a clock-measured cost
    model (id or title)."""
    return any(
        w in segs[i] for i in idx if i < len(segs) and i not in words for w in MEASURED_WORDS
    )


def widen(noisy, segs, markup):
    """`noisy` segments widened to their whole rows."""
    r = rows(segs, markup)
    hit = {r[i] for i in noisy if i < len(segs)}
    return {i for i in range(len(segs)) if r[i] in hit} | noisy


problems, masked = [], 0


SHOW = bool(os.environ.get("SHOW_MASKED"))


def left_out(rel, where, reasons):
    """Counts a difference left out when any of `reasons` (name, test: a function) holds;
    whether it was. The tests run in turn up to the first that holds, every one under
    SHOW_MASKED, which prints those that hold."""
    global masked
    if SHOW:
        why = [w for w, test in reasons if test()]
        if why:
            print(f"masked {rel}: {where} ({','.join(why)})")
    else:
        why = any(test() for _, test in reasons)
    masked += bool(why)
    return bool(why)


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
        noisy = [row_of(q, o) for q in noisy]
        diffs = []
        json_diff(o, n, (), diffs)
        for d in diffs:
            # the innermost object that is a list element (an answer of a per-scene group),
            # else the row (it holds the row's value in either case)
            obj = next(
                (d[: k + 1] for k in reversed(range(len(d)))
                 if isinstance(d[k], int) and isinstance(at_value(o, d[: k + 1]), dict)),
                row_of(d, o),
            )
            if not left_out(rel, shown(d), (
                ("noisy", lambda: any(q[: len(d)] == d or d[: len(q)] == q for q in noisy)),
                ("measured", lambda: names_measured(at_value(o, obj))
                 or names_measured(at_value(n, obj)) or under_measured(o, d)
                 or under_measured(n, d)),
                ("reordered", lambda: reordered_by_measure(o, n, d)),
                ("aggregate", lambda: rel == "answer.json"
                 and any(d[: len(a)] == a for a in AGGREGATES)),
                ("timed", lambda: any(rel.endswith(f) and d[: len(t)] == t for f, t in TIMED)),
            )):
                problems.append(f"{rel}: {shown(d)}: OLD {at(o, d)}, NEW {at(n, d)}")
        continue
    bo, bn = open(po, "rb").read(), open(pn, "rb").read()
    if not rel.endswith(TEXT):
        if bo != bn and not left_out(
            rel, "bytes", (("noisy", lambda: any(open(pa, "rb").read() != bo for pa in pas)),)
        ):
            problems.append(f"{rel}: differs (byte for byte)")
        continue
    markup = rel.endswith((".html", ".svg"))
    to, tn = segments(bo, markup), segments(bn, markup)
    if to == tn:
        continue
    noisy = set()
    for pa in pas:
        noisy |= indices(changed(to, segments(open(pa, "rb").read(), markup)))
    noisy = widen(noisy, to, markup)
    timed = {to[i] for i in noisy}
    sec = sections(to)
    words, words_new = prose(to, markup), prose(tn, markup)
    # sections with rows of a table (not prose) that the runs of OLD differ in
    noisy_sections = {sec[i] for i in noisy if i < len(to) and i not in words}
    r_old, r_new = rows(to, markup), rows(tn, markup)
    members_old, members_new = {}, {}
    for m, r in ((members_old, r_old), (members_new, r_new)):
        for j, k in enumerate(r):
            m.setdefault(k, []).append(j)
    for i1, i2, j1, j2 in changed(to, tn):
        touched = indices([(i1, i2, j1, j2)])
        rows_old = {j for i in touched if i < len(to) for j in members_old[r_old[i]]}
        rows_new = {j for i in range(j1, j2) for j in members_new[r_new[i]]}
        # OLD's segments all timing-dependent; or a run of NEW's segments that OLD has among
        # its timing-dependent rows, moved by the diff's alignment across one of them
        moved = i2 == i1 and all(t in timed for t in tn[j1:j2])
        chart = rel.endswith(".svg") and noisy
        aggregate = all(i in words and sec[i] in noisy_sections for i in touched if i < len(to))
        measured = names_measured_text(to, rows_old, words) or names_measured_text(
            tn, rows_new, words_new
        )
        # where the figures came from: compiled now or read from the compile store
        stored = any(PROVENANCE_TEXT.search(to[i]) for i in rows_old) or any(
            PROVENANCE_TEXT.search(tn[i]) for i in rows_new
        )
        if left_out(rel, f"segment {i1} {' '.join(to[i1:i2])[:120]!r}", (
            ("noisy", lambda: touched <= noisy), ("moved", lambda: moved),
            ("chart", lambda: chart), ("aggregate", lambda: aggregate),
            ("measured", lambda: measured), ("stored", lambda: stored),
        )):
            continue
        problems.append(
            f"{rel}: segment {i1}: OLD {' '.join(to[i1:i2])[:160]!r}, NEW {' '.join(tn[j1:j2])[:160]!r}"
        )
if problems:
    print("\n".join(problems))
    print(f"{len(problems)} differences in {len(fo | fn)} files ({masked} left out as run times)")
    sys.exit(1)
print(f"identical: {len(fo & fn)} files ({masked} differences left out as run times: decided "
      "from a clock by rule, or where the runs of OLD differ too)")
EOF
