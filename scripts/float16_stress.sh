#!/usr/bin/env bash
# Float16 stress of every method (issue 23), timed: `shadelab stress --precision f16` must run
# every method within 60 s on 2 cores. Prints the wall time and the per-method table (valid
# angle at 1/255 in float16 next to float32, non-finite cases) from stress.json.
# Usage: scripts/float16_stress.sh [OUT_DIR [THRESHOLD]]
#   (defaults out/float16_stress and 1/255; the valid angles are at THRESHOLD)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/float16_stress}
THRESHOLD=${2:-1/255}
BIN=${SHADELAB_BIN:-target/release/shadelab}
[ -x "$BIN" ] || cargo build --release --locked
start=$(date +%s.%N)
"$BIN" stress --precision f16 --methods all --threshold "$THRESHOLD" --out "$OUT" > "$OUT.table.txt"
end=$(date +%s.%N)
wall=$(echo "$end - $start" | bc)
python3 - "$OUT/stress.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["precision"] == "f16", r["precision"]
def a(v):
    return "none" if v is None else f"{v:g}"
print(f"{'method':<32} {'valid f16':>10} {'valid f32':>10} {'non-finite f16':>15} {'worst f16':>10}")
for m in sorted(r["methods"], key=lambda m: m["name"]):
    w = m["worst_finite_abs_error"]
    print(f"{m['name']:<32} {a(m['max_valid_angle_deg']):>10} {a(m.get('max_valid_angle_deg_f32')):>10} "
          f"{m['non_finite_cases']:>15} {('-' if w is None else f'{w:.2e}'):>10}")
print(f"threshold {r['threshold']:.6f}; stress.json seconds: {r['seconds']:.1f}")
PY
echo "wall: ${wall} s for every method (limit 60 s on 2 cores)"
