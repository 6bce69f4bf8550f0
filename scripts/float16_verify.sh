#!/usr/bin/env bash
# The float16 twin against the device on every shipped scene and shared model (issue 23):
# `shadelab verify --precision f16` on Vulkan (each float16 device image against its own f64
# formula within the float16 bound, and against the software engine's float16 twin within the
# sum of their bounds) and with `--engine software` (the twin against its own f64 formula).
# Prints one line per scene or model: the largest error/bound over every method of each check,
# the method that reached it, and the verdict (exit status of verify). Exit 1 if any failed.
# Usage: scripts/float16_verify.sh [OUT_DIR [SIZE]]   (defaults out/float16_verify, 96x96;
#   the models come from SHADELAB_MODELS, default ../shared/models)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/float16_verify}
SIZE=${2:-96x96}
MODELS=${SHADELAB_MODELS:-../shared/models}
BIN=${SHADELAB_BIN:-target/release/shadelab}
[ -x "$BIN" ] || cargo build --release --locked
mkdir -p "$OUT"
failed=0
printf '%-22s %-9s %-40s %-40s %-40s %s\n' "scene/model" "engine" "max dI/bound (method)" \
    "max dN/bound (method)" "max twin/bound (method)" "verdict"
for s in scenes/*.toml "$MODELS"/*.obj; do
    [ -e "$s" ] || continue
    case $s in *.toml) arg=(--scene "$s") ;; *) arg=(--mesh "$s") ;; esac
    for engine in vulkan software; do
        log="$OUT/$(basename "$s").$engine.txt"
        if "$BIN" verify "${arg[@]}" --size "$SIZE" --engine "$engine" --precision f16 >"$log" 2>&1; then
            verdict=pass
        else
            verdict="FAIL (exit $?)"
            failed=1
        fi
        python3 - "$log" "$(basename "$s")" "$engine" "$verdict" <<'PY'
import sys
log, name, engine, verdict = sys.argv[1:]
lines = open(log).read().splitlines()
head = next(i for i, l in enumerate(lines) if l.startswith("method "))
cols = lines[head].split()
best = {}
for l in lines[head + 1:]:
    f = l.split()
    if "|" not in f or f.index("|") != cols.index("|"):
        continue
    for c in ("dI/bound", "dN/bound", "twin/bound"):
        if c in cols:
            v = float(f[cols.index(c)])
            if c not in best or v > best[c][0]:
                best[c] = (v, f[0])
cell = lambda c: f"{best[c][0]:.3f} ({best[c][1]})" if c in best else "-"
print(f"{name:<22} {engine:<9} {cell('dI/bound'):<40} {cell('dN/bound'):<40} {cell('twin/bound'):<40} {verdict}")
PY
    done
done
exit $failed
