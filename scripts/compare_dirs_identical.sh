#!/bin/sh
# Issue 26: are two `shadelab compare` output folders the same? summary.json is compared without
# its timing and provenance (top-level `timing`/`provenance`, keys ending in `_ms` or
# `_per_second`), every other file (summary.csv, reference.png, each method's render.png and
# heatmaps) byte for byte, and the two folders must hold the same files. Prints "identical: N
# files" and exits 0, or every difference and exits 1.
# Usage: scripts/compare_dirs_identical.sh BEFORE_DIR AFTER_DIR
# Example: old/shadelab compare --scene scenes/sphere_fine.toml --size 1024x1024 --out /tmp/a
#          target/release/shadelab compare --scene scenes/sphere_fine.toml --size 1024x1024 --out /tmp/b
#          scripts/compare_dirs_identical.sh /tmp/a /tmp/b
set -eu
[ $# -eq 2 ] || { sed -n '2,10p' "$0" >&2; exit 2; }
exec python3 - "$1" "$2" <<'PY'
import json, os, sys, filecmp
a, b = sys.argv[1], sys.argv[2]
def files(d):
    return sorted(os.path.relpath(os.path.join(r, n), d) for r, _, ns in os.walk(d) for n in ns)
fa, fb = files(a), files(b)
bad = []
if fa != fb:
    bad.append(f"file lists differ: only before {sorted(set(fa)-set(fb))}, only after {sorted(set(fb)-set(fa))}")
def strip(x, top=True):
    if isinstance(x, dict):
        return {k: strip(v, False) for k, v in x.items() if not (top and k in ("timing", "provenance")) and not (k.endswith("_ms") or k.endswith("_per_second"))}
    if isinstance(x, list):
        return [strip(v, False) for v in x]
    return x
for f in sorted(set(fa) & set(fb)):
    pa, pb = os.path.join(a, f), os.path.join(b, f)
    if f.endswith("summary.json"):
        if strip(json.load(open(pa))) != strip(json.load(open(pb))):
            bad.append(f"{f}: differs")
    elif not filecmp.cmp(pa, pb, shallow=False):
        bad.append(f"{f}: bytes differ")
print("\n".join(bad) if bad else f"identical: {len(fa)} files (summary.json without timing/provenance, every other file byte for byte)")
sys.exit(1 if bad else 0)
PY
