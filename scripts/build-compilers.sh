#!/usr/bin/env bash
# `make compilers`: the compilers of `shadelab isa`'s phone, board and new-Intel families
# (docs/isa.md "Vendors"), built from Debian's Mesa 25.0.7 source package into the user's cache.
# Nothing is installed system-wide except the Debian build packages named in
# scripts/install-deps.sh (set `compilers`); Debian's apt state is only read.
#
# What it builds (one meson configuration, then exactly these ninja targets):
#   Vulkan : Turnip (Qualcomm Adreno, ir3)
#   OpenGL ES (gallium, EGL surfaceless): panfrost (Mali Midgard, Bifrost, Valhall), lima
#            (Utgard), vc4 and v3d (Broadcom VideoCore), freedreno (Adreno a2xx-a5xx, which
#            Turnip does not take): where no Vulkan driver serves. Not panvk (Mali's Vulkan
#            driver): it offers Vulkan 1.0/1.1 and a code size only, and Mali goes through
#            panfrost's OpenGL ES compiler (docs/isa.md)
#   drm-shims (noop): freedreno, panfrost, lima, vc4, v3d, intel
# then, in a second meson configuration of the same source (asahi needs LLVM: it compiles an
# OpenCL C library of its own with Mesa's mesa_clc at build time; the first configuration
# stays LLVM-free and its drivers unchanged):
#   Vulkan : Honeykrisp (Apple AGX G13, asahi's compiler), its drm-shim (noop). Not the asahi
#            gallium driver: Mesa 25.0.7's gallium loader reaches asahi only as the render half
#            of a display device, so EGL cannot open it on the shim (docs/isa.md)
# and downloads bookworm-backports' ANV 25.0.7 (mesa-vulkan-drivers .deb, unpacked, for Intel
# Meteor Lake, Lunar Lake, Battlemage, Panther Lake under the 25.0.7 Intel shim).
#
# Pinned: the source is Debian's `mesa 25.0.7-2+deb13u1` (.dsc sha256 below; the
# bookworm-backports `25.0.7-2~bpo12+1` .dsc is listed in the archive's index but not served by
# its pool) and the ANV .deb; meson 1.5.2 (wheel sha256 below; Debian 12's meson 1.0 is too old
# for Mesa 25) is pip-installed into the cache. Everything lives under
#   ${XDG_CACHE_HOME:-~/.cache}/shadelab/compilers/mesa-<version>-<sha256 of the .dsc, 16>/
# and ends by writing ${XDG_CACHE_HOME:-~/.cache}/shadelab/vendors/compilers.env (KEY=VALUE lines
# that shadelab reads). Resumable: each step checks what is already there (download by
# checksum, the unpacked source by a stamp, meson's build.ninja, ninja itself), so an
# interrupted run goes on where it stopped; a finished one returns in a second.
# Usage: scripts/build-compilers.sh            (JOBS=n overrides ninja's job count, default 2)
#        scripts/build-compilers.sh --check    (exit 0 when compilers.env and its files are
#                                               there, else 1 with what is missing; builds nothing)
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
# Debian's python3 first (mesa's meson needs its python3-mako and python3-yaml).
export PATH="/usr/bin:$PATH"
base="${XDG_CACHE_HOME:-$HOME/.cache}/shadelab"
cache="$base/compilers"
jobs="${JOBS:-2}"

MESA_VERSION=25.0.7-2+deb13u1
MESA_SUITE=trixie
MESA_DSC_SHA256=c3605bc68cd140db19523c1b80ecd4aa1d77d5b528f15902995ef9ddbbc8f07e
ANV_VERSION=25.0.7-2~bpo12+1
ANV_DEB_SHA256=3899f1800424c60a05df5d6913076a526ca8fdbabec43672cd397563d1ca3263
MESON_VERSION=1.5.2
MESON_WHEEL_SHA256=77706e2368a00d789c097632ccf4fc39251fba56d03e1e1b262559a3c7a08f5b

key="$cache/mesa-$MESA_VERSION-${MESA_DSC_SHA256:0:16}"

if [ "${1:-}" = "--check" ]; then
  env="$base/vendors/compilers.env"
  [ -f "$env" ] || { echo "build-compilers: $env is missing (make compilers)" >&2; exit 1; }
  grep -q "^GLES_LIB=" "$env" ||
    { echo "build-compilers: $env lacks the OpenGL ES drivers (make compilers)" >&2; exit 1; }
  grep -q "^ASAHI_SHIM=" "$env" ||
    { echo "build-compilers: $env lacks the Apple (asahi) route (make compilers)" >&2; exit 1; }
  grep -q "^MESA_SOURCE_SHA256=$MESA_DSC_SHA256\$" "$env" ||
    { echo "build-compilers: $env is of another Mesa source (make compilers)" >&2; exit 1; }
  while IFS='=' read -r k v; do
    case "$v" in /*) [ -e "$v" ] || { echo "build-compilers: $k=$v is missing" >&2; exit 1; } ;; esac
  done <"$env"
  exit 0
fi
log="$key/build.log"
mkdir -p "$key" "$base/vendors"
t0=$(date +%s)

say() { echo "build-compilers: [$(($(date +%s) - t0)) s] $*" >&2; }
fail() {
  say "FAILED: $* (log: $log)"
  tail -n 20 "$log" | sed 's/^/build-compilers:   /' >&2
  exit 1
}

# apt_private: apt-get with a private configuration under $cache/apt/<name>.
. "$here/apt-private.sh"

apt_sources() {
  local name=$1 line=$2
  mkdir -p "$cache/apt/$name"
  echo "$line [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian $3 main" \
    >"$cache/apt/$name/sources.list"
}

sha_ok() { [ -f "$1" ] && [ "$(sha256sum "$1" | cut -d' ' -f1)" = "$2" ]; }

# 1. Build packages (apt lock taken by install-deps.sh).
say "packages (scripts/install-deps.sh compilers)"
"$here/install-deps.sh" compilers >>"$log" 2>&1 || fail "installing the build packages"

# 2. meson into the cache (pip --target, hash-pinned wheel).
meson_dir="$cache/meson-$MESON_VERSION"
if [ ! -f "$meson_dir/.done" ]; then
  say "meson $MESON_VERSION into $meson_dir"
  rm -rf "$meson_dir"
  printf 'meson==%s --hash=sha256:%s\n' "$MESON_VERSION" "$MESON_WHEEL_SHA256" >"$cache/meson-req.txt"
  python3 -m pip install -q --no-deps --require-hashes --target "$meson_dir" \
    -r "$cache/meson-req.txt" >>"$log" 2>&1 || fail "pip install meson"
  touch "$meson_dir/.done"
fi
meson() { PYTHONPATH="$meson_dir" python3 -m mesonbuild.mesonmain "$@"; }

# 3. The source (private apt, deb-src of $MESA_SUITE), checked against the pinned .dsc.
dsc="$key/download/mesa_$MESA_VERSION.dsc"
if ! sha_ok "$dsc" "$MESA_DSC_SHA256" || [ ! -f "$key/download/.done" ]; then
  say "Debian's mesa $MESA_VERSION source (apt-get source, private apt state)"
  apt_sources "$MESA_SUITE-src" deb-src "$MESA_SUITE"
  apt_private "$MESA_SUITE-src" update >>"$log" 2>&1 || fail "apt-get update ($MESA_SUITE deb-src)"
  mkdir -p "$key/download"
  (cd "$key/download" && apt_private "$MESA_SUITE-src" source --download-only \
    "mesa=$MESA_VERSION") >>"$log" 2>&1 || fail "apt-get source mesa=$MESA_VERSION"
  sha_ok "$dsc" "$MESA_DSC_SHA256" || fail "the .dsc's sha256 is not the pinned $MESA_DSC_SHA256"
  touch "$key/download/.done"
fi
src="$key/src"
if [ ! -f "$src/.done" ]; then
  say "unpack the source (dpkg-source checks the tarballs against the pinned .dsc)"
  rm -rf "$src" "$src.partial"
  # Without --no-check, dpkg-source verifies each tarball against the .dsc's checksums; it
  # applies Debian's patches (debian/patches) as Debian's own build does.
  dpkg-source -x "$dsc" "$src.partial" >>"$log" 2>&1 || fail "dpkg-source -x"
  mv "$src.partial" "$src"
  touch "$src/.done"
fi

# 4. ANV 25.0.7 (bookworm-backports' binary .deb, unpacked).
anv="$key/anv"
if [ ! -f "$anv/.done" ]; then
  say "bookworm-backports' mesa-vulkan-drivers $ANV_VERSION (ANV), unpacked"
  apt_sources backports deb "bookworm-backports"
  sed -i 's/^deb \[/deb [arch=amd64 /' "$cache/apt/backports/sources.list"
  apt_private backports update >>"$log" 2>&1 || fail "apt-get update (bookworm-backports)"
  rm -rf "$anv"
  mkdir -p "$anv/download"
  (cd "$anv/download" && apt_private backports download "mesa-vulkan-drivers=$ANV_VERSION") \
    >>"$log" 2>&1 || fail "apt-get download mesa-vulkan-drivers=$ANV_VERSION"
  deb=$(ls "$anv"/download/mesa-vulkan-drivers_*.deb)
  sha_ok "$deb" "$ANV_DEB_SHA256" || fail "$deb's sha256 is not the pinned $ANV_DEB_SHA256"
  dpkg-deb -x "$deb" "$anv/root" >>"$log" 2>&1 || fail "dpkg-deb -x"
  rm -f "$deb"
  touch "$anv/.done"
fi

# 5. meson setup, again only when build.ninja is missing (an interrupted setup starts over) or
# the options changed (a reconfigure keeps what is built).
build="$key/build"
options=(--buildtype=release -Db_ndebug=true --wrap-mode=nodownload
  -Dplatforms= -Degl=enabled -Dglx=disabled -Dgbm=disabled -Dglvnd=disabled
  -Dopengl=true -Dgles1=disabled -Dgles2=enabled
  -Dgallium-drivers=freedreno,panfrost,lima,vc4,v3d -Dvulkan-drivers=freedreno
  -Dvulkan-layers= -Dtools=drm-shim,intel -Dexpat=enabled -Dllvm=disabled
  -Dgallium-va=disabled -Dgallium-vdpau=disabled -Dgallium-xa=disabled
  -Dgallium-nine=false -Dgallium-rusticl=false -Dvideo-codecs=
  -Dvalgrind=disabled -Dlibunwind=disabled -Dlmsensors=disabled -Dzstd=disabled
  -Dbuild-tests=false -Dperfetto=false -Dandroid-libbacktrace=disabled)
if [ ! -f "$build/build.ninja" ]; then
  say "meson setup"
  rm -rf "$build"
  meson setup "$build" "$src" "${options[@]}" >>"$log" 2>&1 || fail "meson setup"
  echo "${options[*]}" >"$build/.shadelab-options"
elif [ "$(cat "$build/.shadelab-options" 2>/dev/null)" != "${options[*]}" ]; then
  say "meson setup --reconfigure (the options changed)"
  meson setup --reconfigure "$build" "$src" "${options[@]}" >>"$log" 2>&1 ||
    fail "meson setup --reconfigure"
  echo "${options[*]}" >"$build/.shadelab-options"
fi

# 6. ninja, exactly the targets the routes use, in two rounds (the Vulkan driver and the shims
# are a few hundred steps; the OpenGL ES libraries, with every gallium driver, most of the
# rest); a progress line every 10 % of each.
vulkan_and_shims=(
  src/freedreno/vulkan/libvulkan_freedreno.so
  src/freedreno/drm-shim/libfreedreno_noop_drm_shim.so
  src/panfrost/drm-shim/libpanfrost_noop_drm_shim.so
  src/gallium/drivers/lima/drm-shim/liblima_noop_drm_shim.so
  src/broadcom/drm-shim/libv3d_noop_drm_shim.so
  src/broadcom/drm-shim/libvc4_noop_drm_shim.so
  src/intel/tools/libintel_noop_drm_shim.so
)
gles=(
  src/egl/libEGL.so.1.0.0
  src/mapi/es2api/libGLESv2.so.2.0.0
)
run_ninja() {
  local dir=$1 what=$2
  shift 2
  say "ninja -j$jobs: $what ($# targets)"
  # PYTHONPATH: when ninja reconfigures (meson.build or a native file changed), it runs
  # `python3 -m mesonbuild` itself, which must be the pinned meson, not the system's.
  PYTHONPATH="$meson_dir" nice -n 19 ninja -C "$dir" -j"$jobs" "$@" 2>&1 | tee -a "$log" |
    awk -v t0="$t0" -v what="$what" '/^\[[0-9]+\/[0-9]+\]/ {
        split(substr($1, 2), a, "/"); n = a[1] + 0; total = a[2] + 0
        pct = int(100 * n / total)
        if (pct >= last + 10 || n == total) {
          last = pct - pct % 10
          cmd = "date +%s"; cmd | getline now; close(cmd)
          printf "build-compilers: [%d s] %s: ninja %d/%d (%d %%)\n", now - t0, what, n, total, pct > "/dev/stderr"
        }
      }'
  [ "${PIPESTATUS[0]}" -eq 0 ] || fail "ninja ($what)"
}
# 7. What the routes read, written after each round (so that a failure in a later one leaves
# the earlier ones' routes usable): ICD manifests with absolute paths, the shims, and after the
# second the EGL/GLES libraries in one folder (LD_LIBRARY_PATH of the OpenGL ES children).
out="$key/out"
icd() {
  mkdir -p "$out/icd"
  cat >"$out/icd/$1.json" <<EOF
{ "ICD": { "api_version": "1.4.305", "library_path": "$2" }, "file_format_version": "1.0.1" }
EOF
}
write_env() {
  local gles=$1 asahi=${2:-no}
  icd turnip "$build/src/freedreno/vulkan/libvulkan_freedreno.so"
  icd anv "$(find "$anv/root" -name libvulkan_intel.so | head -n 1)"
  if [ "$gles" = yes ]; then
    rm -rf "$out/lib"
    mkdir -p "$out/lib"
    for l in libEGL.so.1 libGLESv2.so.2; do
      cp -L "$(find "$build/src" -name "$l" | head -n 1)" "$out/lib/$l"
    done
    for l in $(find "$build/src" -name 'libgallium-*.so' -o -name 'libglapi.so.0'); do
      cp -L "$l" "$out/lib/"
    done
  fi
  if [ "$asahi" = yes ]; then icd asahi "$build_asahi/src/asahi/vulkan/libvulkan_asahi.so"; fi
  {
    echo "MESA_SOURCE=mesa_$MESA_VERSION.dsc"
    echo "MESA_SOURCE_SHA256=$MESA_DSC_SHA256"
    echo "ANV_PACKAGE=mesa-vulkan-drivers_$ANV_VERSION"
    echo "TURNIP_ICD=$out/icd/turnip.json"
    echo "ANV_ICD=$out/icd/anv.json"
    if [ "$gles" = yes ]; then echo "GLES_LIB=$out/lib"; fi
    echo "FREEDRENO_SHIM=$build/src/freedreno/drm-shim/libfreedreno_noop_drm_shim.so"
    echo "PANFROST_SHIM=$build/src/panfrost/drm-shim/libpanfrost_noop_drm_shim.so"
    echo "LIMA_SHIM=$build/src/gallium/drivers/lima/drm-shim/liblima_noop_drm_shim.so"
    echo "V3D_SHIM=$build/src/broadcom/drm-shim/libv3d_noop_drm_shim.so"
    echo "VC4_SHIM=$build/src/broadcom/drm-shim/libvc4_noop_drm_shim.so"
    echo "INTEL_SHIM=$build/src/intel/tools/libintel_noop_drm_shim.so"
    if [ "$asahi" = yes ]; then
      echo "ASAHI_ICD=$out/icd/asahi.json"
      echo "ASAHI_SHIM=$build_asahi/src/asahi/drm-shim/libasahi_noop_drm_shim.so"
    fi
  } >"$base/vendors/compilers.env.partial"
  mv "$base/vendors/compilers.env.partial" "$base/vendors/compilers.env"
}

build_asahi="$key/build-asahi"
run_ninja "$build" "Turnip and the drm-shims" "${vulkan_and_shims[@]}"
write_env no
say "Turnip, ANV 25.0.7 and the shims are ready ($base/vendors/compilers.env)"
run_ninja "$build" "the OpenGL ES drivers" "${gles[@]}"
write_env yes
say "the OpenGL ES drivers are ready ($base/vendors/compilers.env)"

# 8. Honeykrisp (asahi, Apple AGX) in a configuration of its own: LLVM 15 (Debian 12's; meson
# is told which llvm-config, not left to find Debian's default llvm-config of LLVM 14) for
# mesa_clc, which compiles asahi's OpenCL C library (libagx) at build time; nothing of LLVM is
# loaded by the driver at run time. `-Dtools=asahi` because Mesa 25.0.7 enters src/asahi only
# for the gallium driver or the tools (src/meson.build), not for the Vulkan driver alone; only
# the targets below are built. Same rules: set up once, reconfigured when the options change.
# Mesa 25.0.7's Honeykrisp refuses every device before probing it (the asahi kernel interface
# was unstable); under the noop shim that refusal is all that stands in the way: the one change
# to the pinned source, in a file only this configuration compiles (the patch says why).
patch_file="$here/patches/honeykrisp-probe.patch"
# Checked on every run by the refusal's own line, never remembered by a marker file (a source
# unpacked again must be patched again), nor by a reverse dry run (a patch that only removes
# lines reverses "successfully" with fuzz onto the unpatched file).
if grep -q 'Blanket refusal to probe' "$src/src/asahi/vulkan/hk_physical_device.c"; then
  say "patch: Honeykrisp probes the shim ($patch_file)"
  patch -p1 -s -f -F0 -d "$src" <"$patch_file" >>"$log" 2>&1 || fail "patch $patch_file"
  ! grep -q 'Blanket refusal to probe' "$src/src/asahi/vulkan/hk_physical_device.c" ||
    fail "patch $patch_file left the refusal in place"
fi
# Written only when it differs: meson's build.ninja depends on its native file, so a new mtime
# alone would make ninja reconfigure the asahi build at every run.
ini="[binaries]
llvm-config = '/usr/lib/llvm-15/bin/llvm-config'"
[ "$(cat "$key/llvm15.ini" 2>/dev/null)" = "$ini" ] || printf '%s\n' "$ini" >"$key/llvm15.ini"
asahi_options=(--native-file "$key/llvm15.ini" --buildtype=release -Db_ndebug=true
  --wrap-mode=nodownload
  -Dplatforms= -Degl=disabled -Dglx=disabled -Dgbm=disabled -Dglvnd=disabled
  -Dopengl=false -Dgles1=disabled -Dgles2=disabled
  -Dgallium-drivers= -Dvulkan-drivers=asahi -Dvulkan-layers= -Dtools=drm-shim,asahi
  -Dexpat=enabled -Dllvm=enabled -Dshared-llvm=enabled -Ddraw-use-llvm=false
  -Dgallium-va=disabled -Dgallium-vdpau=disabled -Dgallium-xa=disabled
  -Dgallium-nine=false -Dgallium-rusticl=false -Dvideo-codecs=
  -Dvalgrind=disabled -Dlibunwind=disabled -Dlmsensors=disabled -Dzstd=disabled
  -Dbuild-tests=false -Dperfetto=false -Dandroid-libbacktrace=disabled)
if [ ! -f "$build_asahi/build.ninja" ]; then
  say "meson setup (asahi)"
  rm -rf "$build_asahi"
  meson setup "$build_asahi" "$src" "${asahi_options[@]}" >>"$log" 2>&1 || fail "meson setup (asahi)"
  echo "${asahi_options[*]}" >"$build_asahi/.shadelab-options"
elif [ "$(cat "$build_asahi/.shadelab-options" 2>/dev/null)" != "${asahi_options[*]}" ]; then
  say "meson setup --reconfigure (asahi: the options changed)"
  meson setup --reconfigure "$build_asahi" "$src" "${asahi_options[@]}" >>"$log" 2>&1 ||
    fail "meson setup --reconfigure (asahi)"
  echo "${asahi_options[*]}" >"$build_asahi/.shadelab-options"
fi
asahi=(
  src/asahi/vulkan/libvulkan_asahi.so
  src/asahi/drm-shim/libasahi_noop_drm_shim.so
)
run_ninja "$build_asahi" "Honeykrisp (Apple AGX)" "${asahi[@]}"
write_env yes yes
say "done in $(($(date +%s) - t0)) s: $base/vendors/compilers.env"
