#!/bin/sh
# Software engine against lavapipe for the same draw in the same run, then every method's
# software frame time (issue 13). A benchmark, never a test: the figures depend on the machine
# and its load. Usage: scripts/software_bench.sh [SCENE.toml] [SIZE] [REPEAT] [METHODS]
set -eu
cd "$(dirname "$0")/.."
cargo run --release --locked --example software_bench -- \
    "${1:-scenes/sphere_fine.toml}" "${2:-1024}" "${3:-15}" "${4:-all}"
