#!/usr/bin/env bash
# Installs the outside converter the mesh-input tests use into the user's cache, never into the
# repository: CesiumGS's obj2gltf (npm registry, Apache-2.0), which turns the shared OBJ models
# into glTF at test time (tests/inputs/converted.rs; the converted files are not ours to
# commit). Needs node and npm (Debian: nodejs, npm). A second run is free.
#
#   scripts/setup-converters.sh          -> $XDG_CACHE_HOME/shadelab/converters (default ~/.cache)
#   scripts/setup-converters.sh --check  -> exit 0 when obj2gltf is installed, 1 otherwise
set -euo pipefail
version=3.2.0
dir="${XDG_CACHE_HOME:-$HOME/.cache}/shadelab/converters"
bin="$dir/node_modules/.bin/obj2gltf"
if [ -x "$bin" ] && "$bin" --version 2>/dev/null | grep -qx "$version"; then
  exit 0
fi
if [ "${1:-}" = "--check" ]; then
  exit 1
fi
if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then
  echo "setup-converters: node and npm are needed to install obj2gltf (Debian: apt-get install nodejs npm); the converter tests will say SKIPPED" >&2
  exit 2
fi
mkdir -p "$dir"
start=$(date +%s)
# A package.json of its own, so npm installs here and not in a parent folder's project.
[ -f "$dir/package.json" ] || echo '{"name": "shadelab-converters", "private": true}' > "$dir/package.json"
npm install --prefix "$dir" --no-audit --no-fund --loglevel=error "obj2gltf@$version" >&2
"$bin" --version >/dev/null
echo "setup-converters: obj2gltf $version in $dir ($(($(date +%s) - start)) s)" >&2
