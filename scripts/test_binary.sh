# Sourced by scripts that run an ignored test of the library (scripts/colormap_changes.sh,
# scripts/heatmap_colors_exhaustive.sh): builds the release test binary once and sets `bin` to
# it, so that the test runs without a second `cargo test` (which may rebuild: in a git worktree
# build.rs's rerun-if-changed names a .git/HEAD that does not exist). Prints the binary and the
# machine; exits 2 when the build fails or no binary is found.
built=$(cargo test --release --locked --lib --no-run 2>&1) || {
    echo "$built" >&2
    exit 2
}
bin=$(echo "$built" | sed -n 's/.*Executable unittests src\/lib.rs (\(.*\))/\1/p')
echo "test binary: $bin"
[ -x "$bin" ] || { echo "no test binary found" >&2; exit 2; }
echo "$(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
