#!/usr/bin/env bash
# Benchmark of `shadelab isa --calibrate`'s time target (not a test): the micro-kernels on every
# default family set up, timed end to end; prints the wall and CPU time (children included), the
# machine's load before the run, and whether the wall time is within the 60 s budget.
# Usage: scripts/calibrate_bench.sh [RUNS]   (default 1)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-1}
bin=target/release/shadelab
[ -x "$bin" ] || cargo build --release --locked
budget=60
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "calibrate_bench: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
for i in $(seq "$runs"); do
  load=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f "%e %U %S" -o "$out/time" "$bin" isa --calibrate --out "$out/cal" \
    >"$out/stdout" 2>"$out/stderr" || { tail -n 3 "$out/stderr" >&2; exit 1; }
  read -r wall user sys <"$out/time"
  summary=$(tail -n 1 "$out/stdout")
  verdict=$(awk -v w="$wall" -v b="$budget" 'BEGIN { print (w <= b) ? "within" : "OVER" }')
  cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.1f", u + s }')
  echo "run $i: $summary: ${wall} s wall, ${cpu} s CPU, load average ${load} before: ${verdict} the ${budget} s budget"
done
