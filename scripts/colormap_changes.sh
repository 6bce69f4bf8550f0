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
. scripts/test_binary.sh
/usr/bin/time -f "write_colormap_changes: %e s wall, %U s user, %S s sys" \
    "$bin" output::colormap::tests::write_colormap_changes --exact \
    --ignored --nocapture
