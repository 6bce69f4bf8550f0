#!/usr/bin/env bash
# Issues 27 and 39: `shadelab prove --max-angle 90` proves every covered method over both of its
# domains (any triangle, stress's edge) within 1 % gap in 60 s on 2 cores. Prints, from one run,
# the methods covered (and out of reach), the worst relative gap, each method's triangle and
# edge figures, the wall time and the verdict; exits 1 when the run took longer than 60 s or
# some metric is not within the tolerance.
# Usage: scripts/prove_bench.sh [OUT_DIR]   (builds the release binary first)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-$(mktemp -d)/prove}"
cargo build --release --locked --quiet
start=$(date +%s.%N)
taskset -c 0,1 target/release/shadelab prove --max-angle 90 --tolerance 0.01 --out "$out"
end=$(date +%s.%N)
secs=$(echo "$end - $start" | bc)
python3 - "$out/proof.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
gaps = [(x["relative_gap"], m["name"], d["domain"], x["metric"])
        for m in r["methods"] for d in m["domains"] for x in d["metrics"]]
worst = max(gaps, key=lambda g: float("inf") if g[0] is None else g[0])
print(f"methods covered: {len(r['methods'])} ({', '.join(m['name'] for m in r['methods'])})")
print(f"out of reach: {len(r['out_of_reach'])} (reasons in proof.json)")
print(f"worst relative gap: {worst[0]} ({worst[1]} {worst[2]} {worst[3]})")
print("method: length error proven / found, colour proven, valid angle proven (deg), per domain")
for m in r["methods"]:
    parts = []
    for d in m["domains"]:
        x = d["metrics"][0]
        parts.append(f"{d['domain']} {x['proven_upper']:.5g} / {x['found']:.5g}, "
                     f"{d['colour']['proven_upper']:.5g}, {d['max_valid_angle']['proven_deg']}")
    print(f"  {m['name']}: " + "; ".join(parts))
print(f"claims judged by proof: {sum(c['basis'] == 'proven' for c in r['claims'])} of {len(r['claims'])}")
PY
within=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['all_within_tolerance'])" "$out/proof.json")
echo "prove --max-angle 90: ${secs} s wall on cores 0,1; every covered metric within 1 %: ${within}"
if (( $(echo "$secs > 60" | bc) )) || [[ "$within" != "True" ]]; then
  echo "NOT DONE: needs <= 60 s and every metric within tolerance"
  exit 1
fi
echo "done: within 60 s and 1 %"
