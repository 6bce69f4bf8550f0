#!/usr/bin/env bash
# Issue 27's "done when": `shadelab prove --max-angle 90` proves every covered method within
# 1 % gap in 60 s on 2 cores. Prints the wall time, the table and the verdict; exits 1 when
# the run took longer than 60 s or some metric is not within the tolerance.
# Usage: scripts/prove_bench.sh [OUT_DIR]   (builds the release binary first)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-$(mktemp -d)/prove}"
cargo build --release --locked --quiet
start=$(date +%s.%N)
taskset -c 0,1 target/release/shadelab prove --max-angle 90 --tolerance 0.01 --out "$out"
end=$(date +%s.%N)
secs=$(echo "$end - $start" | bc)
within=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['all_within_tolerance'])" "$out/proof.json")
echo "prove --max-angle 90: ${secs} s wall on cores 0,1; every covered metric within 1 %: ${within}"
if (( $(echo "$secs > 60" | bc) )) || [[ "$within" != "True" ]]; then
  echo "NOT DONE: needs <= 60 s and every metric within tolerance"
  exit 1
fi
echo "done: within 60 s and 1 %"
