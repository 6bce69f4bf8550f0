#!/usr/bin/env bash
# Sets up the compiler routes of `shadelab isa` beyond AMD (docs/isa.md "Vendors"), each on its
# own, in the user's cache (nothing installed system-wide but Debian packages through
# scripts/install-deps.sh):
#   intel : Mesa's Intel noop drm-shim (libintel_noop_drm_shim.so), built from the release's own
#           Mesa source package (Debian 12: 22.3.6, Debian 13: 25.0.7; the version of the
#           installed ANV when the archive still has it) with one ninja target; cached under
#           $CACHE/intel/<sha256 of the .dsc>/, rebuilt only when missing. ANV itself is the
#           system's (mesa-vulkan-drivers); intel.env's MESA_VERSION says which Mesa the shim is
#           (Mesa 25's serves Meteor Lake to Panther Lake too, without `make compilers`).
#   gl    : the nouveau and radeon noop drm-shims of Debian's mesa-drm-shim .deb (Debian 12 has
#           none: bookworm-backports'; Debian 13: its own, the installed Mesa's version),
#           downloaded with a private apt configuration and unpacked under
#           $CACHE/gl/<sha256 of the .deb>/ (the OpenGL route: the system's nouveau and r600).
# $CACHE is ${XDG_CACHE_HOME:-~/.cache}/shadelab/vendors. Each route ends by writing
# $CACHE/<route>.env (KEY=VALUE lines that shadelab reads); a route whose .env and files are
# there is left alone (no network). A route that fails names its step and its log, and the
# others still run. Exit status: 0 when every route asked for is set up, 1 otherwise.
# Usage: scripts/setup-vendors.sh [intel] [gl]   (default: both)
set -uo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
self="$here/$(basename "$0")"
# Debian's python3 first (mesa's meson needs its python3-mako; a pyenv shim's python lacks it).
export PATH="/usr/bin:$PATH"
cache="${XDG_CACHE_HOME:-$HOME/.cache}/shadelab/vendors"
mkdir -p "$cache/logs"

say() { echo "setup-vendors: $*" >&2; }

# apt_private: apt-get with a private configuration under $cache/apt/<name>.
. "$here/apt-private.sh"

# The release whose Mesa source and shim are fetched (bookworm on Debian 12, trixie on 13).
release=$("$here/install-deps.sh" --release)
release=${release:-bookworm}
keyring="signed-by=/usr/share/keyrings/debian-archive-keyring.gpg"

# The .env of a route holds KEY=VALUE lines; every value that is a path must exist.
ready() {
  local env="$cache/$1.env"
  [ -f "$env" ] || return 1
  local k v
  while IFS='=' read -r k v; do
    case "$v" in /*) [ -e "$v" ] || return 1 ;; esac
  done <"$env"
  return 0
}

# Runs step $2 of route $1 (the rest is the command), logging to $cache/logs/<route>.log.
step() {
  local route=$1 name=$2
  shift 2
  say "$route: $name"
  # A fresh bash with -e (bash ignores -e in a function called under `if` or `||`): the step
  # stops at its first failing command.
  if ! bash "$self" --step "$@" >>"$cache/logs/$route.log" 2>&1; then
    say "$route: FAILED at step '$name' (log: $cache/logs/$route.log)"
    tail -n 15 "$cache/logs/$route.log" | sed "s/^/setup-vendors: $route:   /" >&2
    return 1
  fi
}

intel_source() {
  local dir="$cache/apt/$release-src"
  mkdir -p "$dir"
  {
    echo "deb-src [$keyring] http://deb.debian.org/debian $release main"
    echo "deb-src [$keyring] http://deb.debian.org/debian $release-updates main"
    echo "deb-src [$keyring] http://deb.debian.org/debian-security $release-security main"
  } >"$dir/sources.list"
  apt_private "$release-src" update
  # The installed ANV's version when the archive has its source, else the release's newest.
  local installed want
  installed=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
  want=mesa
  if [ -n "$installed" ] && apt_private "$release-src" source --print-uris "mesa=$installed" \
    >/dev/null 2>&1; then
    want="mesa=$installed"
  fi
  echo "source: $want of $release (installed ANV: ${installed:-none})"
  rm -rf "$cache/intel/download"
  mkdir -p "$cache/intel/download"
  (cd "$cache/intel/download" && apt_private "$release-src" source --download-only "$want")
}

intel_build() {
  local dsc sha key src build
  dsc=$(ls -t "$cache"/intel/download/mesa_*.dsc | head -n 1)
  sha=$(sha256sum "$dsc" | cut -d' ' -f1)
  key="$cache/intel/$sha"
  if [ -f "$key/libintel_noop_drm_shim.so" ]; then
    echo "already built: $key"
  else
    src="$key/src"
    build="$key/build"
    rm -rf "$src" "$build"
    mkdir -p "$key"
    dpkg-source --no-check -x "$dsc" "$src"
    # Only the shim: no drivers, no window systems, no LLVM (../shared TOOLCHAIN "Other
    # vendors' production-path compilers"): one target, about 180 ninja steps (22.3.6). The
    # options this Mesa has: 22.3 still knows dri-drivers, 25.0 needs expat for the tools.
    local extra=() opts
    opts=$(cat "$src"/meson_options.txt "$src"/meson.options 2>/dev/null || true)
    case "$opts" in *"'dri-drivers'"*) extra+=(-Ddri-drivers=) ;; esac
    case "$opts" in *"'expat'"*) extra+=(-Dexpat=enabled) ;; esac
    meson setup "$build" "$src" --buildtype=release -Dvulkan-drivers= -Dgallium-drivers= \
      -Dtools=drm-shim,intel -Dplatforms= -Dllvm=disabled -Dglx=disabled \
      -Degl=disabled -Dgbm=disabled -Dopengl=false -Dgles1=disabled -Dgles2=disabled \
      -Dvalgrind=disabled -Dlibunwind=disabled -Dlmsensors=disabled -Dzstd=disabled \
      -Dbuild-tests=false "${extra[@]}"
    ninja -C "$build" src/intel/tools/libintel_noop_drm_shim.so
    cp "$build/src/intel/tools/libintel_noop_drm_shim.so" "$key/"
    # Keep the shim and the .dsc (its key); the sources and build are 500 MB.
    rm -rf "$src" "$build"
    find "$cache/intel/download" -type f ! -name '*.dsc' -delete
  fi
  local version
  version=$(basename "$dsc" .dsc)
  {
    echo "SHIM=$key/libintel_noop_drm_shim.so"
    echo "SOURCE=$(basename "$dsc")"
    echo "SOURCE_SHA256=$sha"
    echo "MESA_VERSION=${version#mesa_}"
  } >"$cache/intel.env"
}

gl_download() {
  # Debian 12 has no mesa-drm-shim: bookworm-backports' (Mesa 25.0.7, libc only); later
  # releases their own, of the installed Mesa's version when the archive has it.
  local suite=$release arch installed want
  [ "$release" = bookworm ] && suite=bookworm-backports
  arch=$(dpkg --print-architecture)
  local dir="$cache/apt/$suite"
  mkdir -p "$dir"
  echo "deb [arch=$arch $keyring] http://deb.debian.org/debian $suite main" >"$dir/sources.list"
  apt_private "$suite" update
  installed=$(dpkg-query -W -f='${Version}' libgl1-mesa-dri 2>/dev/null || true)
  want=mesa-drm-shim
  if [ "$suite" = "$release" ] && [ -n "$installed" ] &&
    apt_private "$suite" download --print-uris "mesa-drm-shim=$installed" >/dev/null 2>&1; then
    want="mesa-drm-shim=$installed"
  fi
  echo "package: $want of $suite (installed Mesa: ${installed:-none})"
  rm -rf "$cache/gl/download"
  mkdir -p "$cache/gl/download"
  (cd "$cache/gl/download" && apt_private "$suite" download "$want")
}

gl_unpack() {
  local deb sha key lib
  deb=$(ls "$cache"/gl/download/mesa-drm-shim_*.deb | head -n 1)
  sha=$(sha256sum "$deb" | cut -d' ' -f1)
  key="$cache/gl/$sha"
  rm -rf "$key"
  mkdir -p "$key"
  dpkg-deb -x "$deb" "$key/root"
  lib=$(dirname "$(find "$key/root" -name libnouveau_noop_drm_shim.so | head -n 1)")
  [ -f "$lib/libnouveau_noop_drm_shim.so" ] && [ -f "$lib/libradeon_noop_drm_shim.so" ]
  {
    echo "NOUVEAU_SHIM=$lib/libnouveau_noop_drm_shim.so"
    echo "RADEON_SHIM=$lib/libradeon_noop_drm_shim.so"
    echo "SOURCE=$(basename "$deb")"
    echo "SOURCE_SHA256=$sha"
  } >"$cache/gl.env"
}

# Whether intel.env's shim is of the installed ANV's Mesa (major version): a shim built on
# another release (an upgraded system) is built again.
intel_matches() {
  local installed
  installed=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
  [ -z "$installed" ] ||
    grep -q -e "^MESA_VERSION=${installed%%.*}\." -e "^SOURCE=mesa_${installed%%.*}\." \
      "$cache/intel.env"
}

setup_intel() {
  ready intel && intel_matches && { say "intel: set up ($cache/intel.env)"; return 0; }
  step intel "packages (scripts/install-deps.sh intel)" "$here/install-deps.sh" intel || return 1
  step intel "$release's Mesa source (apt-get source, private apt state)" intel_source || return 1
  step intel "build the noop drm-shim (meson, ninja)" intel_build || return 1
  say "intel: set up ($cache/intel.env)"
}

setup_gl() {
  ready gl && { say "gl: set up ($cache/gl.env)"; return 0; }
  step gl "packages (scripts/install-deps.sh gl)" "$here/install-deps.sh" gl || return 1
  step gl "download Debian's mesa-drm-shim (private apt state)" gl_download || return 1
  step gl "unpack the .deb into the cache" gl_unpack || return 1
  say "gl: set up ($cache/gl.env)"
}

if [ "${1:-}" = "--step" ]; then
  shift
  set -e
  "$@"
  exit 0
fi

status=0
for route in "${@:-intel gl}"; do
  for r in $route; do
    start=$(date +%s)
    case "$r" in
      intel) setup_intel || status=1 ;;
      gl) setup_gl || status=1 ;;
      *) say "unknown route '$r' (expected intel or gl)"; exit 2 ;;
    esac
    say "$r: $(($(date +%s) - start)) s"
  done
done
exit $status
