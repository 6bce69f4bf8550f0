#!/usr/bin/env bash
# Issue 26: the FLIP phase of `shadelab compare`, per method, for one or more binaries (never run
# by the tests). Usage: scripts/flip_bench.sh [RUNS] BINARY...
#   RUNS (default 3) rounds; each round runs every BINARY once, back to back, on
#   `compare --scene scenes/sphere_fine.toml --size 1024x1024 --methods gouraud,flat,mikami_const`
#   (three of the 18 methods that differ from the reference in 10,000 pixels or more: FLIP
#   covers the sphere's box). Prints per run: summary.json's flip_ms / 3 (FLIP per method: the wall time of the FLIP
#   phase summed over the workers), its reference_ms (the reference, including the FLIP
#   reference half since this branch), and user + sys CPU of the process.
#   On a shared machine say "busy" beside any figure.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=3
if [[ ${1:-} =~ ^[0-9]+$ ]]; then runs=$1; shift; fi
[ $# -ge 1 ] || { sed -n '2,11p' "$0" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
methods=gouraud,flat,mikami_const
echo "== FLIP per method, compare --scene scenes/sphere_fine.toml --size 1024x1024 --methods $methods"
echo "   load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
for r in $(seq "$runs"); do
  for bin in "$@"; do
    rm -rf "$tmp/out"
    /usr/bin/time -f '%U %S' -o "$tmp/time" "$bin" compare --scene scenes/sphere_fine.toml \
      --size 1024x1024 --methods "$methods" --out "$tmp/out" >/dev/null 2>"$tmp/err" || {
      echo "flip_bench: $bin failed:" >&2; cat "$tmp/err" >&2; exit 2; }
    python3 - "$tmp/out/summary.json" "$tmp/time" "$bin" "$r" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["timing"]
u, s = map(float, open(sys.argv[2]).read().split()[-2:])
print(f"run {sys.argv[4]} {sys.argv[3]}: flip per method {t['flip_ms'] / 3:.0f} ms, "
      f"reference {t['reference_ms']:.0f} ms, CPU {u + s:.2f} s")
PY
  done
done
echo "   load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
