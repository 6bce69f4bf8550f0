#!/bin/sh
# The anchor benchmark of issue 13: software phong_exact against lavapipe for the same draw in
# the same run, paired per round (median ratio with its sign-test 95% interval, and whether it
# is within 2x, computed by the example), with a breakdown of the software frame. A benchmark,
# never a test: the figures depend on the machine and its load. Every method's software frame
# time, paired against phong_exact, is `shadelab bench --engine software`.
# Usage: scripts/software_bench.sh [SCENE.toml] [SIZE] [ROUNDS]
set -eu
cd "$(dirname "$0")/.."
cargo run --release --locked --example software_bench -- \
    "${1:-scenes/sphere_fine.toml}" "${2:-1024}" "${3:-21}"
