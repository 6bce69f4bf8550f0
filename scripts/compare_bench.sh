#!/usr/bin/env bash
# Issue 26: the cost of a method in `shadelab compare` (never run by the tests).
# Usage: scripts/compare_bench.sh [RUNS] [BINARY] [SIZE]
#   RUNS (default 3) interleaved pairs of `compare --scene scenes/sphere_fine.toml --size SIZE`
#   (default 1024x1024): all methods, then phong_exact alone, each a fresh process writing every
#   file. Per run: wall time, CPU time (user + sys) and peak resident memory of each, and the
#   ratio t(all) / t(phong_exact) of wall times (target <= 4) and of CPU times; then the medians,
#   the marginal cost of a method, (t(all) - t(phong_exact)) / (N - 1) with N the methods of the
#   all run (the rows of its summary.csv), of wall and CPU time (target <= 0.1 s wall), the
#   machine (CPU model, cores) and the load average before and after. BINARY defaults to
#   target/release/shadelab. On a shared machine the wall times and their ratio say little:
#   read the CPU ratio and say "busy" beside any figure.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3}
bin=${2:-target/release/shadelab}
size=${3:-1024x1024}
[ -x "$bin" ] || { echo "compare_bench: build first (make build) or name a binary" >&2; exit 2; }
command -v /usr/bin/time >/dev/null || { echo "compare_bench: needs /usr/bin/time (GNU time)" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# one compare; prints "wall cpu peak_mb"
one() { # METHODS DIR
  /usr/bin/time -f '%e %U %S %M' -o "$tmp/time" "$bin" compare --scene scenes/sphere_fine.toml \
    --size "$size" --methods "$1" --out "$2" >"$tmp/stdout" 2>"$tmp/stderr" || {
    echo "compare_bench: compare --methods $1 failed:" >&2; cat "$tmp/stderr" >&2; exit 2; }
  awk '{ printf "%.2f %.2f %.0f\n", $1, $2 + $3, $4 / 1024 }' "$tmp/time"
}

echo "== compare --scene scenes/sphere_fine.toml --size $size: all methods vs phong_exact alone, $runs runs"
echo "   binary: $bin ($("$bin" --version 2>/dev/null || echo unknown version))"
echo "   load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%4s %10s %10s %8s %10s %10s %8s %9s %9s\n' run all_wall_s all_cpu_s all_MB \
  one_wall_s one_cpu_s one_MB ratio_wall ratio_cpu
: >"$tmp/rows"
for i in $(seq "$runs"); do
  rm -rf "$tmp/all" "$tmp/one"
  read -r aw ac am < <(one all "$tmp/all")
  read -r ow oc om < <(one phong_exact "$tmp/one")
  rw=$(awk -v a="$aw" -v b="$ow" 'BEGIN { printf "%.2f", a / b }')
  rc=$(awk -v a="$ac" -v b="$oc" 'BEGIN { printf "%.2f", a / b }')
  # N: the methods of the all run, one row each in its summary.csv (a header line above them)
  n=$(awk 'END { print NR - 1 }' "$tmp/all/summary.csv")
  [ "$n" -gt 1 ] || { echo "compare_bench: the all run compared $n methods" >&2; exit 2; }
  mw=$(awk -v a="$aw" -v b="$ow" -v n="$n" 'BEGIN { printf "%.3f", (a - b) / (n - 1) }')
  mc=$(awk -v a="$ac" -v b="$oc" -v n="$n" 'BEGIN { printf "%.3f", (a - b) / (n - 1) }')
  printf '%4s %10s %10s %8s %10s %10s %8s %9s %9s\n' "$i" "$aw" "$ac" "$am" "$ow" "$oc" "$om" "$rw" "$rc"
  echo "$aw $ac $am $ow $oc $om $rw $rc $mw $mc $n" >>"$tmp/rows"
done
med() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
col() { awk -v c="$1" '{ print $c }' "$tmp/rows" | med; }
echo "median: all $(col 1) s wall, $(col 2) s CPU, peak $(awk '{print $3}' "$tmp/rows" | sort -g | tail -1) MB (max);" \
  "phong_exact $(col 4) s wall, $(col 5) s CPU; ratio $(col 7) wall (target <= 4), $(col 8) CPU;" \
  "peak memory target <= 600 MB"
echo "marginal cost per method, (t(all) - t(phong_exact)) / (N - 1) with N = $(col 11) methods:" \
  "$(col 9) s wall (target <= 0.1 s), $(col 10) s CPU (medians of the runs)"
echo "   machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
echo "   load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
