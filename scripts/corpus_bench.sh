#!/usr/bin/env bash
# Issue 25's speed figure: the five shared models at 256x256, every method, as one corpus
# (one shard, the static GPU cost included when the RADV ICD is present), wall time printed.
# Goal: within 60 s on 2 cores. Usage: scripts/corpus_bench.sh [MODELS_DIR] [extra corpus flags]
set -euo pipefail
cd "$(dirname "$0")/.."
models=${1:-${SHADELAB_MODELS:-../shared/models}}
shift || true
[ -d "$models" ] || { echo "corpus_bench: no models folder $models" >&2; exit 2; }
cargo build --release --locked >/dev/null 2>&1 || cargo build --release --locked
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
n=$(find "$models" -name '*.obj' | wc -l)
start=$(date +%s%N)
code=0
target/release/shadelab corpus "$models" --out "$out/shard" --size 256x256 --methods all "$@" \
  >/dev/null 2>"$out/stderr" || code=$?
end=$(date +%s%N)
ms=$(( (end - start) / 1000000 ))
grep -E "^corpus: (shard|\[)" "$out/stderr" >&2 || true
printf 'corpus: %d meshes at 256x256, every method, %s cores: %d.%d s (exit %d; goal 60 s)\n' \
  "$n" "$(nproc)" $((ms / 1000)) $((ms % 1000 / 100)) "$code"
