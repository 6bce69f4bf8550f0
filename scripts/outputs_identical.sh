#!/bin/sh
# Output identity of two shadelab binaries (issue 20, "every output figure is unchanged"): runs
# `compare` (all methods) on every shipped scene of scenes/ and `stress` (it takes no scene: its
# grid is the same for all) with each binary, then diffs summary.json, summary.csv and
# stress.json. Timing and provenance are left out of the JSON files (top-level `timing` and
# `provenance`, any key ending in `_ms` or `_per_second`, and `elapsed_s`/`seconds` keys): they
# depend on the machine's load and on the binary's git revision, not on the figures. The CSV
# holds no timing and is compared byte for byte. Prints "identical" and exits 0, or prints every
# difference and exits 1 (2 on a usage error or a run that failed).
#
# Usage: scripts/outputs_identical.sh BEFORE_BINARY AFTER_BINARY [SIZE] [WORK_DIR]
#   SIZE defaults to 128x128 (compare only); WORK_DIR to a fresh temporary folder (kept, and
#   printed, so the outputs can be read afterwards).
#        scripts/outputs_identical.sh --diff-only WORK_DIR   (diff the outputs of an earlier run)
# Example: scripts/outputs_identical.sh /tmp/shadelab-d03b5b8 target/release/shadelab
set -eu
if [ $# -lt 2 ]; then
    sed -n '2,16p' "$0" >&2
    exit 2
fi
cd "$(dirname "$0")/.."
if [ "$1" = --diff-only ]; then
    work=$2
else
    before=$(realpath "$1")
    after=$(realpath "$2")
    size=${3:-128x128}
    work=${4:-$(mktemp -d "${TMPDIR:-/tmp}/outputs_identical.XXXXXX")}
    mkdir -p "$work"
    echo "outputs in $work" >&2
fi

run() { # NAME BINARY
    for scene in scenes/*.toml; do
        s=$(basename "$scene" .toml)
        "$2" compare --scene "$scene" --size "$size" --methods all --out "$work/$1/compare/$s" \
            >"$work/$1/compare-$s.log" 2>&1 || {
            echo "$1: compare on $scene failed (see $work/$1/compare-$s.log)" >&2
            exit 2
        }
    done
    "$2" stress --out "$work/$1/stress" >"$work/$1/stress.log" 2>&1 || {
        echo "$1: stress failed (see $work/$1/stress.log)" >&2
        exit 2
    }
}
if [ "$1" != --diff-only ]; then
    mkdir -p "$work/before" "$work/after"
    run before "$before"
    run after "$after"
fi

python3 - "$work" <<'EOF'
import json, os, sys

work = sys.argv[1]
DROP_TOP = {"timing", "provenance"}


def timing_key(k):
    return k.endswith("_ms") or k.endswith("_per_second") or k in ("elapsed_s", "seconds")


def strip(x, top=True):
    if isinstance(x, dict):
        return {
            k: strip(v, False)
            for k, v in x.items()
            if not (top and k in DROP_TOP) and not timing_key(k)
        }
    if isinstance(x, list):
        return [strip(v, False) for v in x]
    return x


def diff(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a:
                out.append(f"{path}.{k}: only after")
            elif k not in b:
                out.append(f"{path}.{k}: only before")
            else:
                diff(a[k], b[k], f"{path}.{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: {len(a)} items before, {len(b)} after")
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, f"{path}[{i}]", out)
    elif type(a) != type(b) or a != b:
        # JSON numbers compare exactly: the same bits print the same shortest text.
        out.append(f"{path}: {a!r} before, {b!r} after")


files = []
for root, _, names in os.walk(os.path.join(work, "before")):
    for n in names:
        if n in ("summary.json", "summary.csv", "stress.json"):
            files.append(os.path.relpath(os.path.join(root, n), os.path.join(work, "before")))
for root, _, names in os.walk(os.path.join(work, "after")):
    for n in names:
        if n in ("summary.json", "summary.csv", "stress.json"):
            rel = os.path.relpath(os.path.join(root, n), os.path.join(work, "after"))
            if rel not in files:
                files.append(rel)
files.sort()
problems = []
for rel in files:
    a, b = (os.path.join(work, side, rel) for side in ("before", "after"))
    if not os.path.exists(a) or not os.path.exists(b):
        problems.append(f"{rel}: only {'after' if os.path.exists(b) else 'before'}")
        continue
    if rel.endswith(".csv"):
        la, lb = open(a).read().splitlines(), open(b).read().splitlines()
        if la != lb:
            for i in range(max(len(la), len(lb))):
                x = la[i] if i < len(la) else "<none>"
                y = lb[i] if i < len(lb) else "<none>"
                if x != y:
                    problems.append(f"{rel}:{i + 1}: before {x}")
                    problems.append(f"{rel}:{i + 1}: after  {y}")
        continue
    out = []
    diff(strip(json.load(open(a))), strip(json.load(open(b))), "", out)
    problems += [f"{rel}: {d}" for d in out]
scenes = sum(1 for f in files if f.endswith("summary.json"))
if not files or scenes == 0 or not any(f.endswith("stress.json") for f in files):
    print(f"nothing to compare: found {files}")
    sys.exit(1)
if problems:
    print("\n".join(problems))
    print(f"{len(problems)} differences in {len(files)} files")
    sys.exit(1)
print(f"identical ({len(files)} files: summary.json and summary.csv of {scenes} scenes, stress.json)")
EOF
