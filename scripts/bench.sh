#!/usr/bin/env bash
# Benchmarks of README "Performance" and "Bench" (never run by the tests).
# Usage: scripts/bench.sh [RUNS]
#  1. process start to PNG written: `shadelab render` of the fine sphere at 1024x1024, warm
#     (one untimed run first fills Mesa's shader cache), median and range of RUNS runs;
#  2. per-frame draw time of phong_exact against the constant-colour floor (`shadelab bench`);
#  3. `shadelab compare` of all methods at 1024x1024 on the fine sphere (renders, statistics,
#     FLIP, every PNG): wall time and peak resident memory;
#  4. `shadelab stress` of all methods: wall time and peak resident memory.
# Usage: scripts/bench.sh skip: per shipped scene and shared model, `shadelab skips` at 1024x1024
#  (the draw before and after culling and leaving out the normal target, a depth pre-pass, front-to-back
#  order and auto at 1/255, paired in the same rounds), then auto's error against its budget at
#  512x512 and 1024x1024 (compare).
# Usage: scripts/bench.sh paired [RUNS] [KEEP_DIR] [-- EXTRA BENCH ARGS]
#  The paired-ratio bar of README "Bench": RUNS (default 3) runs of the default bench of all
#  methods with the control on the fine sphere at 1024x1024; for each run, the paired ratio of
#  phong_exact_control to phong_exact with its 95% interval (the bar: within +-1 %), the widest
#  interval of the run, the rounds, why they stopped and the run's wall time; then the setup
#  (CPU, Mesa, LLVM, LP_NUM_THREADS, load average). Extra arguments go to every bench
#  (e.g. `-- --until-ci 1 --threads 2`). With KEEP_DIR, each run's files stay in KEEP_DIR/run<i>.
#  Run it on an idle machine: on a shared one, say so beside the figures.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/shadelab
[ -x "$bin" ] || { echo "bench: build first (make build)" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

if [ "${1:-}" = paired ]; then
  shift
  runs=3; keep=
  if [ $# -gt 0 ] && [ "$1" != -- ]; then runs=$1; shift; fi
  if [ $# -gt 0 ] && [ "$1" != -- ]; then keep=$1; shift; fi
  [ "${1:-}" = -- ] && shift
  extra=("$@")
  echo "== paired ratio of phong_exact_control to phong_exact, $runs runs (bar: interval within +-1 %)"
  echo "   load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
  for i in $(seq "$runs"); do
    dir="$tmp/run$i"; [ -n "$keep" ] && dir="$keep/run$i"
    rm -rf "$dir"; mkdir -p "$dir"
    cmd=("$bin" bench --scene scenes/sphere_fine.toml --size 1024x1024 --control ${extra[@]+"${extra[@]}"} --out "$dir")
    [ "$i" = 1 ] && echo "   command: ${cmd[*]/$dir/DIR}"
    s=$(date +%s%N)
    "${cmd[@]}" >"$dir/stdout.txt" 2>"$dir/stderr.txt" || { echo "run $i failed: see $dir/stderr.txt" >&2; cat "$dir/stderr.txt" >&2; exit 2; }
    e=$(date +%s%N)
    python3 - "$dir/bench.json" "$i" "$(( (e - s) / 1000000 ))" <<'PY'
import json, sys
b = json.load(open(sys.argv[1]))
c = next(m for m in b["methods"] if m["name"] == "phong_exact_control")
lo, med, hi = c["ratio_ci95_low"], c["ratio_median"], c["ratio_ci95_high"]
pm = max(med - lo, hi - med) / med * 100
r = b["rounds"]
print(f"run {sys.argv[2]}: phong_exact_control / phong_exact = {med:.4f} [{lo:.4f}, {hi:.4f}] "
      f"(+-{pm:.2f} %, {'within' if pm <= 1.0 else 'NOT within'} +-1 %); "
      f"phong_exact {next(m for m in b['methods'] if m['name'] == 'phong_exact')['median_ms']:.2f} ms, "
      f"floor {b['floor']['median_ms']:.2f} ms; widest interval +-{r['widest_half_width_pct'] or float('nan'):.2f} % "
      f"({r['widest']}); {r['rounds']} rounds, {r['stopped']}; total {int(sys.argv[3]) / 1000:.1f} s")
PY
  done
  python3 - "$dir/bench.json" <<'PY'
import json, sys
b = json.load(open(sys.argv[1]))
p = b["provenance"]
print(f"   setup: {b['cpu_model']} ({b['cpu_count']} CPUs), Mesa {p['mesa_version']}, LLVM {p['llvm_version']}, "
      f"LP_NUM_THREADS={b['lp_num_threads'] or 'unset'}, clock {b['clock']['clock']}")
PY
  echo "   load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
  exit 0
fi

if [ "${1:-}" = skip ]; then
  # What skipping saves and what auto costs, per shipped scene and shared model:
  #  1. back-face culling: fragment invocations and draw time of phong_exact with --cull none
  #     and --cull auto (two bench runs: not paired; the README says so);
  #  2. auto at 512x512 and 1024x1024: its worst error (luminance and every channel) against
  #     its budget 1/255 (compare --methods auto), and what each method got.
  models=()
  [ -d ../shared/models ] && models=(../shared/models/*.obj)
  echo "== skips: $bin skips --SCENE --size 1024x1024 --repeat 30 (paired, same rounds); ratios to the default draw"
  echo "| scene | triangles | culled | invocations none -> default | default / none | + pre-pass | + front to back | auto at 1/255 |"
  echo "|---|---:|---|---|---|---|---|---|"
  for sc in scenes/*.toml "${models[@]}"; do
    flag=--scene; case "$sc" in *.obj) flag=--mesh ;; esac
    "$bin" skips $flag "$sc" --size 1024x1024 --repeat 30 --out "$tmp/skips" >/dev/null 2>"$tmp/skips.err" || { cat "$tmp/skips.err" >&2; exit 2; }
    python3 - "$sc" "$tmp/skips/skips.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[2]))
rows = {r["name"]: r for r in s["rows"]}
d = next(r for r in s["rows"] if r["is_default"])
def ratio(r, k):
    x = r[k]
    return f"{x['median']:.3f} [{x['ci95_low']:.3f}, {x['ci95_high']:.3f}] {r['speed_vs_' + k.split('_to_')[1]]}"
def extra(flag):
    r = next((r for r in s["rows"] if r["variant"][flag] and not r["variant"]["auto"]), None)
    return ratio(r, "ratio_to_default") if r else "n/a"
auto = next(r for r in s["rows"] if r["variant"]["auto"])
n0, n1 = rows["none"]["fragment_invocations"], d["fragment_invocations"]
print(f"| {sys.argv[1].split('/')[-1]} | {s['triangles']} | {'yes' if s['culls'] else 'no'} | {n0:,} -> {n1:,} | "
      f"{ratio(d, 'ratio_to_none')} | {extra('prepass')} | {extra('front_to_back')} | {ratio(auto, 'ratio_to_default')} |")
PY
  done
  echo "== auto: $bin compare --SCENE --size S --methods auto,phong_exact --error-budget 0.00392156862745098"
  for sc in scenes/*.toml "${models[@]}"; do
    flag=--scene; case "$sc" in *.obj) flag=--mesh ;; esac
    for size in 512 1024; do
      "$bin" compare $flag "$sc" --size ${size}x${size} --methods auto,phong_exact --error-budget 0.00392156862745098 --out "$tmp/auto" >/dev/null 2>&1
      python3 - "$sc" "$size" "$tmp/auto/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[3]))
a = next(m for m in s["methods"] if m["name"] == "auto")
w = max([a["max_abs_error"]] + [c["max_abs_error"] for c in a["channels"]])
b = s["auto"]["budget"]
got = ", ".join(f"{n} {k}" for n, k in s["auto"]["triangles"] if k)
print(f"{sys.argv[1]} {sys.argv[2]}px: worst {w:.3e} vs budget {b:.3e} ({'within' if w <= b else 'OVER'}); "
      f"non-finite {a['non_finite_pixels']}; {got}; chosen in {s['auto']['choice_ms']:.0f} ms")
PY
    done
  done
  exit 0
fi

runs=${1:-15}
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
