#!/usr/bin/env bash
# Verdict stability of README "Bench" (issue 21 §1; never run by the tests).
# Usage: scripts/verdict_stability.sh [INVOCATIONS] [KEEP_DIR] [-- EXTRA BENCH ARGS]
#  INVOCATIONS (default 3) back-to-back invocations of the default bench: all methods on the
#  fine sphere at 1024x1024 (`shadelab bench` with its default --runs, 5 fresh processes each).
#  Then, per program, its frame-time verdict (speed_vs_phong_exact) and isolated-cost verdict
#  (isolated_vs_phong_exact) in every invocation, and the counts of changes between
#  invocations, pair by pair:
#   - defects: faster <-> slower (cheaper <-> dearer): a verdict that reverses;
#   - near the boundary: faster or slower <-> inconclusive (cheaper or dearer <->
#     indistinguishable): expected now and then, counted;
#   - phong_exact_control not inconclusive (or too_noisy) in some invocation: counted, for the
#     frame time and for the isolated cost (not indistinguishable), with each invocation's
#     run seeds and the isolated control's per-run ratios.
#  Exit 1 when there is a defect or a control is not inconclusive everywhere. With 5 runs an
#  unbiased control still excludes 1 in 1 invocation of 16 per measure (all five runs on one
#  side of 1: 2/32), so a single too_noisy is not by itself a defect: count them over many.
#  Extra arguments go to every bench (e.g. `-- --runs 7`). With KEEP_DIR each invocation's
#  files stay in KEEP_DIR/inv<i>. Run it on an idle machine; on a shared one, say so.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/shadelab
[ -x "$bin" ] || { echo "verdict_stability: build first (make build)" >&2; exit 2; }
n=3; keep=
if [ $# -gt 0 ] && [ "$1" != -- ]; then n=$1; shift; fi
if [ $# -gt 0 ] && [ "$1" != -- ]; then keep=$1; shift; fi
[ "${1:-}" = -- ] && shift
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
base=${keep:-$tmp}
files=()
for i in $(seq 1 "$n"); do
  dir="$base/inv$i"; mkdir -p "$dir"
  s=$(date +%s)
  echo "verdict_stability: invocation $i of $n" >&2
  "$bin" bench --scene scenes/sphere_fine.toml --size 1024x1024 --out "$dir" "$@" > "$dir/stdout.txt"
  echo "verdict_stability: invocation $i took $(( $(date +%s) - s )) s" >&2
  files+=("$dir/bench.json")
done
python3 - "${files[@]}" <<'PY'
import itertools, json, sys
runs = [json.load(open(f)) for f in sys.argv[1:]]
def verdicts(key):
    out = {}
    for r in runs:
        for m in r["methods"]:
            out.setdefault(m["name"], []).append(m.get(key))
    return out
opposite = {("faster", "slower"), ("cheaper", "dearer")}
undecided = {"inconclusive", "indistinguishable", None}
defects = boundary = 0
for key in ["speed_vs_phong_exact", "isolated_vs_phong_exact"]:
    print(f"{key}:")
    for name, vs in verdicts(key).items():
        for a, b in itertools.combinations(vs, 2):
            if (a, b) in opposite or (b, a) in opposite:
                defects += 1
            elif a != b and (a in undecided) != (b in undecided):
                boundary += 1
        changed = "" if len(set(vs)) == 1 else "   <- changed"
        print(f"  {name:<34} {' '.join(str(v) for v in vs)}{changed}")
control = [m["speed_vs_phong_exact"] for r in runs for m in r["methods"] if m["name"] == "phong_exact_control"]
bad_control = sum(1 for v in control if v != "inconclusive")
iso_control = [m.get("isolated_vs_phong_exact") for r in runs for m in r["methods"] if m["name"] == "phong_exact_control"]
bad_iso = sum(1 for v in iso_control if v not in ("indistinguishable", None))
print(f"invocations: {len(runs)}; runs per invocation: {[ (r.get('runs') or {}).get('count', 1) for r in runs ]}")
print(f"seconds per invocation: {[round(r.get('total_s', 0)) for r in runs]}")
for i, r in enumerate(runs, 1):
    rr = r.get("runs") or {}
    iso = rr.get("isolated_control") or {}
    ctl = [m for m in r["methods"] if m["name"] == "phong_exact_control"]
    per_run = [f.get("isolated_ratio_median") for f in (ctl[0].get("run_figures") if ctl else [])]
    print(f"  invocation {i}: seeds {rr.get('seeds')}; isolated control per run {per_run}; "
          f"spread {iso.get('spread')}, too_noisy {iso.get('too_noisy')}")
print(f"changes faster<->slower (defects): {defects}")
print(f"changes between a verdict and inconclusive (pairs of invocations): {boundary}")
print(f"phong_exact_control not inconclusive (frame time): {bad_control} of {len(control)}")
print(f"phong_exact_control not indistinguishable (isolated cost): {bad_iso} of {len(iso_control)}")
sys.exit(1 if defects or bad_control or bad_iso else 0)
PY
