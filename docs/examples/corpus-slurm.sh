#!/usr/bin/env bash
# shadelab corpus on a Slurm cluster: one job array (a shard per task) and a merge job that
# runs when every task has ended (afterany: a shard with a failed mesh exits 1 and is merged).
#
# Submit from a login node, on a filesystem every node sees:
#   docs/examples/corpus-slurm.sh CORPUS_DIR OUT_DIR [TASKS]
# It submits itself as the array (sbatch --array=1-TASKS) and prints
#   array JOBID
#   merge JOBID
# Each task runs `shadelab corpus CORPUS_DIR --out OUT_DIR/shard-<task>` and takes its shard
# from SLURM_ARRAY_TASK_ID (counted from SLURM_ARRAY_TASK_MIN) of SLURM_ARRAY_TASK_COUNT; the
# merge job writes OUT_DIR/merged (corpus.json, corpus.csv, index.html).
# Settings (environment): SHADELAB (the binary; default: shadelab on PATH), SHADELAB_SIZE
# (default 256x256), SHADELAB_METHODS (default all), SHADELAB_CORPUS_ARGS (more flags for
# corpus, e.g. "--bench --runs 5"), SBATCH_ARGS (more flags for sbatch: partition, time).
#SBATCH --job-name=shadelab-corpus
#SBATCH --cpus-per-task=1
set -euo pipefail

SHADELAB=${SHADELAB:-shadelab}
if [ -n "${SHADELAB_CORPUS_TASK:-}" ]; then
  # One array task: a shard of the corpus.
  : "${SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}"
  # shellcheck disable=SC2086
  exec "$SHADELAB" corpus "$SHADELAB_CORPUS_DIR" --out "$SHADELAB_OUT/shard-$SLURM_ARRAY_TASK_ID" \
    --size "${SHADELAB_SIZE:-256x256}" --methods "${SHADELAB_METHODS:-all}" ${SHADELAB_CORPUS_ARGS:-}
fi

if [ $# -lt 2 ]; then
  echo "usage: $0 CORPUS_DIR OUT_DIR [TASKS]" >&2
  exit 2
fi
corpus=$(cd "$1" && pwd)
mkdir -p "$2"
out=$(cd "$2" && pwd)
tasks=${3:-4}
export SHADELAB SHADELAB_CORPUS_DIR="$corpus" SHADELAB_OUT="$out" SHADELAB_CORPUS_TASK=1
# shellcheck disable=SC2086
array=$(sbatch --parsable --export=ALL --array="1-$tasks" -o "$out/slurm-%A_%a.out" \
  ${SBATCH_ARGS:-} "$0")
echo "array $array"
shards=$(for k in $(seq 1 "$tasks"); do printf ' %q' "$out/shard-$k"; done)
# shellcheck disable=SC2086
merge=$(sbatch --parsable --export=ALL --dependency="afterany:$array" -o "$out/slurm-merge-%j.out" \
  ${SBATCH_ARGS:-} --job-name=shadelab-merge \
  --wrap "$(printf '%q' "$SHADELAB") merge$shards --out $(printf '%q' "$out/merged")")
echo "merge $merge"
