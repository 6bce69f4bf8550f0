#!/bin/sh
# Issue 26: writes src/output/colormap_changes.rs, the heatmap colormaps' colour change points
# over [0, 1] (src/output/colormap.rs `Changes`), from an exhaustive scan of every f32 bit
# pattern from 0 to 1.0 (about 1.07e9 per colormap, magma and RdBu) with the exact spline
# `Table::rgb`, over all cores: runs the ignored test `write_colormap_changes`. Prints the
# number of pieces per colormap and the run's time. Commit the file it writes; the suite checks
# the lookup against the spline, scripts/heatmap_colors_exhaustive.sh against colorous on every
# f32 in [0, 1].
# Usage: scripts/colormap_changes.sh
set -eu
cd "$(dirname "$0")/.."
# Build once and run the test binary itself (see scripts/heatmap_colors_exhaustive.sh).
built=$(cargo test --release --locked --lib --no-run 2>&1) || {
    echo "$built" >&2
    exit 2
}
bin=$(echo "$built" | sed -n 's/.*Executable unittests src\/lib.rs (\(.*\))/\1/p')
echo "test binary: $bin"
[ -x "$bin" ] || { echo "no test binary found" >&2; exit 2; }
echo "$(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
/usr/bin/time -f "write_colormap_changes: %e s wall, %U s user, %S s sys" \
    "$bin" output::colormap::tests::write_colormap_changes --exact \
    --ignored --nocapture
