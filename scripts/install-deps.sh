#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages shadelab needs, only when one is missing.
#   run time : libvulkan1 (the loader), mesa-vulkan-drivers (lavapipe)
#   build    : libshaderc-dev (+ glslang-dev, spirv-tools: static libs shaderc-sys links)
#   tests    : vulkan-validationlayers (Khronos validation), spirv-tools (spirv-val),
#              chromium (headless: the HTML report's browser test),
#              slurm-wlm + munge (a single-node Slurm on localhost: the corpus job-array test)
#   intel    : what scripts/setup-vendors.sh needs to build Mesa's Intel noop drm-shim from
#              Debian's Mesa source (meson, ninja, mako, bison, flex, libdrm/expat/zlib headers,
#              dpkg-dev for `apt-get source`)
#   compilers: what scripts/build-compilers.sh needs to build Mesa 25.0.7's Turnip, panvk,
#              OpenGL ES drivers and drm-shims (meson itself is pip-installed into the cache:
#              Debian 12's is too old), glslang-tools (Turnip's internal shaders)
#   gl       : the OpenGL route of `shadelab isa` (nouveau, r600): Mesa's EGL and DRI drivers,
#              spirv-cross (SPIR-V to GLSL)
# Usage: scripts/install-deps.sh [run|build|test|intel|compilers|gl]...   (default: run build test)
set -euo pipefail

want=()
for set in "${@:-run build test}"; do
  for s in $set; do
    case "$s" in
      run) want+=(libvulkan1 mesa-vulkan-drivers) ;;
      build) want+=(libshaderc-dev glslang-dev spirv-tools pkg-config) ;;
      test) want+=(vulkan-validationlayers spirv-tools chromium slurm-wlm munge) ;;
      intel) want+=(meson ninja-build python3-mako bison flex libdrm-dev libexpat1-dev zlib1g-dev
                    pkg-config dpkg-dev xz-utils ca-certificates) ;;
      compilers) want+=(ninja-build python3-mako python3-yaml python3-pip bison flex gcc g++
                        libdrm-dev libexpat1-dev zlib1g-dev pkg-config dpkg-dev xz-utils
                        glslang-tools ca-certificates
                        llvm-15-dev libclang-15-dev libclang-cpp15-dev libclc-15
                        libllvmspirvlib-15-dev) ;;
      gl) want+=(libegl1 libegl-mesa0 libgl1-mesa-dri spirv-cross ca-certificates) ;;
      *) echo "install-deps: unknown set '$s' (expected run, build, test, intel, compilers or gl)" >&2; exit 2 ;;
    esac
  done
done

missing=()
for p in "${want[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    case " ${missing[*]-} " in *" $p "*) ;; *) missing+=("$p") ;; esac
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

if ! command -v apt-get >/dev/null 2>&1; then
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: no apt-get here; install the equivalents of these Debian packages by hand" >&2
  exit 2
fi
if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  sudo=(sudo -n)
elif command -v sudo >/dev/null 2>&1 && [ -t 0 ]; then
  sudo=(sudo)
else
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: not root and no usable sudo; run as root: apt-get install ${missing[*]}" >&2
  exit 2
fi
echo "install-deps: installing ${missing[*]}" >&2
# One apt at a time on this machine: two apt-get runs at once (two checkouts building side by
# side) break each other's update. flock waits for the other one to finish.
if command -v flock >/dev/null 2>&1; then
  exec 9>"${TMPDIR:-/tmp}/shadelab-apt.lock"
  flock 9
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
