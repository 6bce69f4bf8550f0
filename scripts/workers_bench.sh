#!/usr/bin/env bash
# The compiler workers' figures (docs/figures.md "compiler workers" rows), with a compile store
# and a Mesa shader cache of their own (temporary folders: the user's are neither read nor
# changed):
#   1. `shadelab isa --method-file NEW --methods NEW` on every family set up, NEW a method file
#      never compiled (a fresh comment in it), phong_exact already in the store; with the
#      workers, then with one child per request (SHADELAB_NO_WORKERS=1, another fresh NEW);
#   2. `shadelab tune --error-budget 1/255` on a mesh never seen (MESH's vertices moved by up to
#      1e-3 with a random seed: new coefficients, new programs) after scenes/torus.obj (the
#      store warm for the baselines);
#   3. `shadelab report --scenes scenes --out R` (`make demo`'s report) from the empty store
#      and Mesa cache, with the peak of the workers' resident memory together (every
#      `shadelab child --worker` process, sampled every 0.2 s).
# Per step: wall seconds and the load average before it (the machine is shared: state the load
# with the figure).
# Usage: scripts/workers_bench.sh [--no-report] [MESH]   (MESH default: ../shared/models/teapot.obj
#   or scenes/sphere_coarse.obj; builds the release binary first)
set -euo pipefail
cd "$(dirname "$0")/.."
report=1
if [[ "${1:-}" == --no-report ]]; then report=0; shift; fi
mesh="${1:-${SHADELAB_MODELS:-../shared/models}/teapot.obj}"
[[ -f "$mesh" ]] || mesh=scenes/sphere_coarse.obj
cargo build --release --locked --quiet
bin=target/release/shadelab
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export SHADELAB_STORE="$work/store" MESA_SHADER_CACHE_DIR="$work/mesa"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"

load() { cut -d' ' -f1-3 /proc/loadavg; }
seconds() { # seconds of "$@" (its stdout dropped)
  local start end
  start=$(date +%s.%N); "$@" > /dev/null; end=$(date +%s.%N)
  echo "$end - $start" | bc
}
fresh_method() { # a method file nobody compiled: $1/newton_two_steps.glsl
  mkdir -p "$1"
  { echo "// fresh: $RANDOM$RANDOM$(date +%N)"
    echo "// shadelab-inputs: interpolated_normal"
    echo "real3 methodNormal() {"
    echo "    real3 n = R3(vNormal);"
    echo "    real z = dot(n, n);"
    echo "    real y = R(0.5) * (R(3.0) - z);"
    echo "    y = y * (R(1.5) - R(0.5) * z * y * y);"
    echo "    return n * y;"
    echo "}"; } > "$1/newton_two_steps.glsl"
  echo "$1/newton_two_steps.glsl"
}

"$bin" isa -q --methods phong_exact --out "$work/isa0" > /dev/null
for mode in workers children; do
  f=$(fresh_method "$work/$mode")
  before=$(load)
  if [[ $mode == children ]]; then export SHADELAB_NO_WORKERS=1; fi
  s=$(seconds "$bin" isa -q --method-file "$f" --methods newton_two_steps --out "$work/isa-$mode")
  unset SHADELAB_NO_WORKERS
  n=$(python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print(sum(f['supported'] for f in r['families']))" "$work/isa-$mode/isa.json")
  echo "isa-new-method ($mode): $s s on $n families (load before: $before)"
done

"$bin" tune -q --mesh scenes/torus.obj --error-budget 1/255 --out "$work/tune-torus" > /dev/null
python3 - "$mesh" "$work/unseen.obj" <<'PY'
import random, sys
random.seed()
with open(sys.argv[2], "w") as out:
    for l in open(sys.argv[1]):
        if l.startswith("v "):
            x, y, z = (float(t) + random.uniform(-1e-3, 1e-3) for t in l.split()[1:4])
            l = f"v {x} {y} {z}\n"
        out.write(l)
PY
before=$(load)
s=$(seconds "$bin" tune -q --mesh "$work/unseen.obj" --error-budget 1/255 --out "$work/tune-unseen")
python3 - "$work/tune-unseen/tune.json" "$s" "$before" "$(basename "$mesh")" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
t = r["timings"]
costed = sum(1 for c in r["candidates"] if not c.get("not_costed"))
print(f"tune-unseen-mesh ({sys.argv[4]} moved): {float(sys.argv[2]):.1f} s (costs {t['costs_s']:.1f} s; "
      f"{costed} of {len(r['candidates'])} candidates costed; "
      f"{sum(a['error'] is None for a in r['cost_models'])} of {len(r['cost_models'])} models measured) "
      f"(load before: {sys.argv[3]})")
PY

if (( report )); then
  peak="$work/peak"
  echo 0 > "$peak"
  ( max=0
    while sleep 0.2; do
      kb=0
      for p in $(pgrep -f "shadelab child --worker" || true); do
        r=$(awk '/^VmRSS:/ {print $2}' "/proc/$p/status" 2>/dev/null || echo 0)
        kb=$(( kb + ${r:-0} ))
      done
      if (( kb > max )); then max=$kb; echo "$max" > "$peak"; fi
    done ) &
  sampler=$!
  before=$(load)
  s=$(seconds "$bin" report --scenes scenes --out "$work/report" 2> "$work/report.err")
  kill "$sampler" 2> /dev/null || true
  echo "report-empty-store: $s s; the workers' peak resident memory together $(( $(cat "$peak") / 1024 )) MiB (load before: $before)"
fi
