#!/usr/bin/env bash
# Benchmarks of README "Performance" (never run by the tests). Usage: scripts/bench.sh [RUNS]
#  1. process start to PNG written: `shadelab render` of the fine sphere at 1024x1024, warm
#     (one untimed run first fills Mesa's shader cache), median and range of RUNS runs;
#  2. per-frame draw time of phong_exact against the constant-colour floor (`shadelab bench`);
#  3. `shadelab compare` of all methods at 1024x1024 on the fine sphere (renders, statistics,
#     FLIP, every PNG): wall time and peak resident memory;
#  4. `shadelab stress` of all methods: wall time and peak resident memory.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-15}
bin=target/release/shadelab
[ -x "$bin" ] || { echo "bench: build first (make build)" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cmd=("$bin" render --scene scenes/sphere_fine.toml --size 1024x1024 --out "$tmp/f.png")
echo "== process start to PNG written: ${cmd[*]/$tmp/TMP}"
"${cmd[@]}"
times=()
for _ in $(seq "$runs"); do
  s=$(date +%s%N); "${cmd[@]}"; e=$(date +%s%N)
  times+=($(( (e - s) / 1000000 )))
done
sorted=($(printf '%s\n' "${times[@]}" | sort -n))
echo "runs $runs: median ${sorted[$((runs / 2))]} ms, min ${sorted[0]} ms, max ${sorted[$((runs - 1))]} ms"
echo
echo "== per-frame draw time: $bin bench --scene scenes/sphere_fine.toml --size 1024x1024 --methods phong_exact --out TMP/bench"
"$bin" bench --scene scenes/sphere_fine.toml --size 1024x1024 --methods phong_exact --out "$tmp/bench" 2>/dev/null

echo
ccmd=("$bin" compare --scene scenes/sphere_fine.toml --size 1024x1024 --out "$tmp/cmp")
echo "== compare, all methods, 1024x1024 (3 runs; targets: <= 10 s wall, <= 600 MB peak RSS): ${ccmd[*]/$tmp/TMP}"
for _ in 1 2 3; do
  rm -rf "$tmp/cmp"
  # wall time and the child's peak resident set size (getrusage), then the phase timings
  python3 - "${ccmd[@]}" <<'PY'
import resource, subprocess, sys, time
s = time.monotonic()
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
wall = time.monotonic() - s
rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
print(f"wall {wall:.2f} s, peak RSS {rss:.0f} MB", end="; ")
PY
  python3 -c "import json,sys; t=json.load(open(sys.argv[1]))['timing']; print(', '.join(f'{k} {v:.0f}' for k,v in t.items()))" "$tmp/cmp/summary.json"
done

echo
scmd=("$bin" stress --out "$tmp/stress")
echo "== stress, all methods (target <= 60 s): ${scmd[*]/$tmp/TMP}"
python3 - "${scmd[@]}" <<'PY'
import resource, subprocess, sys, time
s = time.monotonic()
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
wall = time.monotonic() - s
rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
print(f"wall {wall:.2f} s, peak RSS {rss:.0f} MB")
PY
