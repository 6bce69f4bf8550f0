#!/usr/bin/env bash
# Issue 26: how low the cost of a method in `shadelab compare` can go while every output stays
# bit-identical (never run by the tests; needs `perf`, run on an idle machine).
# Usage: scripts/compare_floor.sh [BINARY] [SIZE]
#   Profiles `compare --scene scenes/sphere_fine.toml --size SIZE` (default 1024x1024) of all
#   methods and of phong_exact alone with `perf record -e cpu-clock -F 1000` (one sample = 1 ms
#   of CPU) and sorts every sample into one of four parts:
#     lavapipe  llvmpipe's threads, and lavapipe's own code in any thread (libvulkan_lvp, the
#               shaders it compiled ([JIT]), libLLVM): drawing the method;
#     libm      glibc's libm (powf in FLIP, acos of the normal angle, log10 of the heatmaps'
#               log scale): their exact bits are the figures;
#     png       the PNG encoder (fdeflate, png's filters, checksums): its bytes are the files;
#     rest      everything else: the analysis, heatmaps, read-back, allocation, start-up.
#   The first three are the floor: they stay as long as every byte of every output stays. It
#   prints the CPU seconds of each part in both runs, then the floor of the marginal cost of a
#   method, (floor(all) - floor(one)) / (N - 1) / 2 (both cores busy, the rest free), and the
#   ratio t(all) / t(one) it allows, with t(one) the median wall time of three runs of
#   phong_exact alone without perf (perf's own writing makes profiled wall times longer).
#   The queue thread's copies inside lavapipe (memmove in libc) count as "rest": the floor is a
#   lower bound.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/shadelab}
size=${2:-1024x1024}
[ -x "$bin" ] || { echo "compare_floor: build first (make build) or name a binary" >&2; exit 2; }
command -v perf >/dev/null || { echo "compare_floor: needs perf (linux-perf)" >&2; exit 2; }
command -v /usr/bin/time >/dev/null || { echo "compare_floor: needs /usr/bin/time (GNU time)" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# profile one compare; prints "lavapipe libm png rest wall" (seconds)
profile() { # METHODS NAME
  /usr/bin/time -f '%e' -o "$tmp/$2.time" perf record -q -e cpu-clock -F 1000 -o "$tmp/$2.data" \
    "$bin" compare --scene scenes/sphere_fine.toml --size "$size" --methods "$1" \
    --out "$tmp/$2" >"$tmp/$2.stdout" 2>"$tmp/$2.stderr" || {
    echo "compare_floor: compare --methods $1 failed:" >&2; cat "$tmp/$2.stderr" >&2; exit 2; }
  perf report -i "$tmp/$2.data" --no-children -g none -n --sort comm,dso,symbol --stdio -q \
    -t $'\t' 2>/dev/null | awk -F'\t' -v wall="$(cat "$tmp/$2.time")" '
    { n = $2 + 0; comm = $3; dso = $4; sym = $5; gsub(/ +$/, "", comm); gsub(/ +$/, "", dso)
      if (comm ~ /^llvmpipe/ || dso ~ /libvulkan_lvp|libLLVM|^\[JIT\]/) part = "lavapipe"
      else if (dso ~ /^libm\.so/) part = "libm"
      else if (sym ~ /fdeflate::|png::|crc32|adler/) part = "png"
      else part = "rest"
      s[part] += n }
    END { printf "%.2f %.2f %.2f %.2f %.2f\n", s["lavapipe"] / 1000, s["libm"] / 1000,
          s["png"] / 1000, s["rest"] / 1000, wall }'
}

echo "== compare --scene scenes/sphere_fine.toml --size $size: the floor of a method's cost"
echo "   binary: $bin ($("$bin" --version 2>/dev/null || echo unknown version))"
echo "   machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
echo "   load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
read -r al am ap ar aw < <(profile all all)
read -r ol om op or ow < <(profile phong_exact one)
for i in 1 2 3; do
  /usr/bin/time -f '%e' -o "$tmp/one$i.time" "$bin" compare --scene scenes/sphere_fine.toml \
    --size "$size" --methods phong_exact --out "$tmp/one$i" >/dev/null 2>&1
done
t1=$(cat "$tmp"/one[123].time | sort -n | sed -n 2p)
n=$(($(wc -l <"$tmp/all/summary.csv") - 1))
printf '%-12s %9s %9s %9s %9s %9s %14s\n' run lavapipe_s libm_s png_s rest_s cpu_s profiled_wall_s
for r in "all $al $am $ap $ar $aw" "phong_exact $ol $om $op $or $ow"; do
  set -- $r
  printf '%-12s %9s %9s %9s %9s %9.2f %14s\n' "$1" "$2" "$3" "$4" "$5" \
    "$(awk -v a="$2" -v b="$3" -v c="$4" -v d="$5" 'BEGIN { print a + b + c + d }')" "$6"
done
awk -v n="$n" -v al="$al" -v am="$am" -v ap="$ap" -v ar="$ar" -v aw="$aw" \
  -v ol="$ol" -v om="$om" -v op="$op" -v or="$or" -v ow="$ow" -v t1="$t1" 'BEGIN {
  floor = (al + am + ap - ol - om - op) / (n - 1) / 2
  rest = (ar - or) / (n - 1) / 2
  printf "methods: %d\n", n
  printf "floor of the marginal cost (lavapipe + libm + png, both cores): %.3f s wall per method\n", floor
  printf "the rest now (analysis, heatmaps, read-back, ...), both cores:    %.3f s wall per method\n", rest
  printf "lowest ratio t(all) / t(phong_exact) with the rest free: %.2f (t(phong_exact) = %.2f s wall, median of 3 unprofiled runs)\n", (t1 + (n - 1) * floor) / t1, t1
  printf "ratio with the rest as now: %.2f\n", (t1 + (n - 1) * (floor + rest)) / t1
}'
echo "   load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
