#!/usr/bin/env bash
# auto's frame check per shipped scene and shared model (issue 22): `shadelab skips` times auto
# (after its frame check) against the default phong_exact draw in the same rounds.
# Usage: scripts/auto_frame.sh [SIZE (1024)] [REPEAT (30)] [COST_MODEL (lavapipe)]
# Prints a markdown table: what auto chose per triangle, what it drew, the frame check's
# grouped / one-program ratio and decision, and auto's frame over the default draw.
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-1024}; repeat=${2:-30}; model=${3:-lavapipe}
bin=target/release/shadelab
[ -x "$bin" ] || cargo build --release --locked
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
models=()
[ -n "${SHADELAB_MODELS:-}" ] && [ -d "$SHADELAB_MODELS" ] && models=("$SHADELAB_MODELS"/*.obj)
echo "== $bin skips --SCENE --size ${size}x${size} --repeat $repeat --cost-model $model (load before: $(cut -d' ' -f1-3 /proc/loadavg))"
echo "| scene | chosen per triangle | drawn | frame check: grouped / one program | decision | auto / default |"
echo "|---|---|---|---|---|---|"
for sc in scenes/*.toml "${models[@]}"; do
  flag=--scene; case "$sc" in *.obj) flag=--mesh ;; esac
  "$bin" skips $flag "$sc" --size "${size}x${size}" --repeat "$repeat" --cost-model "$model" \
    --out "$tmp/skips" >/dev/null 2>"$tmp/err" || { cat "$tmp/err" >&2; exit 2; }
  python3 - "$sc" "$tmp/skips/skips.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[2]))
a = s["auto"]; g = a.get("grouping") or {}
drawn = ", ".join(f"{n} {k}" for n, k in a["triangles"] if k)
f = g.get("frame")
def num(x): return "n/a" if x is None else f"{x:.3f}"
check = (f"{num(f['ratio_median'])} [{num(f['ratio_ci95_low'])}, {num(f['ratio_ci95_high'])}] "
         f"({f['rounds']} rounds; model: {100 * f['predicted_saving']:.1f} % less shading)") if f else "not needed (one program)"
auto = next(r for r in s["rows"] if r["variant"]["auto"])
x = auto["ratio_to_default"]
print(f"| {sys.argv[1].split('/')[-1]} | {g.get('programs_chosen', 1)} programs | {drawn} | {check} | "
      f"{g.get('decision', 'one program')} | {x['median']:.3f} [{x['ci95_low']:.3f}, {x['ci95_high']:.3f}] {auto['speed_vs_default']} |")
PY
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
