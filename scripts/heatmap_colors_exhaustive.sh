#!/bin/sh
# Issue 26: the heatmaps' colormaps (src/output/colormap.rs `Colormap::rgb`: the generated
# region table src/output/colormap_changes.rs, the spline where the table leaves it) against
# colorous on every f32 in [0, 1] (about 1.07e9 inputs per colormap, magma and RdBu), over all
# cores: runs the ignored
# test `every_f32_in_0_1_matches_colorous`, which prints one line per colormap and fails with the
# first input where the two colours differ. The suite checks a stride of the same range and
# every segment boundary. Prints the machine and the run's time; exits with the test's status.
# Usage: scripts/heatmap_colors_exhaustive.sh
set -eu
cd "$(dirname "$0")/.."
. scripts/test_binary.sh
/usr/bin/time -f "every_f32_in_0_1_matches_colorous: %e s wall, %U s user, %S s sys" \
    "$bin" every_f32_in_0_1_matches_colorous --ignored --nocapture
