#!/usr/bin/env bash
# Fuzzes the untrusted-input readers (OBJ, scene TOML, stress --replay cases, glTF, PLY; tests/fuzz.rs lists them) with the
# harness of tests/fuzz/: 1,000,000 inputs in total by default, about a minute on one core.
# Prints per target and in total: inputs tried, time, panics, inputs over 1 s or over the
# allocation limit, and the slowest input. Exits non-zero on any of those failures; failing
# inputs are saved under target/tmp/fuzz/ (keep each as a regression file in
# tests/data/fuzz/TARGET/ once the reader is fixed). A fuzzed .gltf never reaches the disk: its
# buffer files read as one fixed buffer, and asking for one outside the input's folder fails the
# input; the buffer URI rule on the disk (links, FIFOs, devices) has deterministic tests in
# tests/fuzz.rs that every `cargo test` runs.
#
#   scripts/fuzz.sh [INPUTS]        e.g. scripts/fuzz.sh 5000000
#   SHADELAB_FUZZ_SEED=N            another random sequence (default 10)
#   SHADELAB_FUZZ_TARGETS=obj,scene only these targets
#   SHADELAB_MODELS=DIR             more OBJ seeds (default ../shared/models when present)
set -euo pipefail
cd "$(dirname "$0")/.."
export SHADELAB_FUZZ_INPUTS="${1:-1000000}"
if [[ -z "${SHADELAB_MODELS:-}" && -d ../shared/models ]]; then
    SHADELAB_MODELS="$(cd ../shared/models && pwd)"
    export SHADELAB_MODELS
fi
start=$(date +%s)
status=0
cargo test --release --locked --quiet --test integration -- --ignored --exact fuzz::full_run \
    --nocapture 2>&1 | grep -E '^fuzz:|panicked|FATAL|test result' || status=1
echo "fuzz.sh: $(($(date +%s) - start)) s wall (build included), exit $status"
exit $status
