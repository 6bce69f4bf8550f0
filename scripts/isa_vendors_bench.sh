#!/usr/bin/env bash
# Benchmark of issue 40's speed target (not a test): every method on every family of Intel,
# NVIDIA and AMD TeraScale (`shadelab isa`, each family in its own child, two at a time), timed
# end to end; prints the wall and CPU time, the machine's load, and whether it is within the
# 30 s budget. The routes must be set up (scripts/setup-vendors.sh).
# Usage: scripts/isa_vendors_bench.sh [RUNS]   (default 3; the figure is each run's)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3}
bin=target/release/shadelab
[ -x "$bin" ] || cargo build --release --locked
families=intel:skl,intel:icl,intel:tgl,intel:adl,intel:dg2,nvidia:nvc0,nvidia:nve4,nvidia:nv117,nvidia:nv134,nvidia:nv162,terascale:cypress,terascale:cayman
budget=30
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "isa_vendors_bench: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
for i in $(seq "$runs"); do
  load=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f "%e %U %S" -o "$out/time" "$bin" isa --methods all --families "$families" \
    --out "$out/isa" >"$out/stdout" 2>"$out/stderr"
  read -r wall user sys <"$out/time"
  summary=$(tail -n 1 "$out/stdout")
  case "$summary" in
    "12 families (12 compiled)"*) ;;
    *) echo "isa_vendors_bench: not every family compiled: $summary" >&2; exit 1 ;;
  esac
  rows=$(echo "$summary" | sed -E 's/.*compiled\), ([0-9]+) rows.*/\1/')
  verdict=$(awk -v w="$wall" -v b="$budget" 'BEGIN { print (w <= b) ? "within" : "OVER" }')
  cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.1f", u + s }')
  echo "run $i: 37 methods x 12 families ($rows rows): ${wall} s wall, ${cpu} s CPU (children included), load average ${load} before: ${verdict} the ${budget} s budget"
done
