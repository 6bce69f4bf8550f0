#!/usr/bin/env bash
# Installs the system packages shadelab needs, only when one is missing. Knows Debian 12
# (bookworm) and Debian 13 (trixie), whose package names are the same for every set below; on
# another distribution it says which package of what role to install (and, on one derived from
# Debian with apt-get, tries Debian's names).
#   run      : libvulkan1 (the Vulkan loader), mesa-vulkan-drivers (lavapipe, RADV, ANV)
#   build    : a C toolchain (gcc, g++: cargo's linker and the C++ runtime; make; git),
#              pkg-config, ca-certificates (cargo fetches crates over TLS), libshaderc-dev + glslang-dev + spirv-tools (the shader compiler's
#              libraries, which build.rs finds and links)
#   tests    : vulkan-validationlayers (Khronos validation), spirv-tools (spirv-val),
#              chromium (headless: the HTML report's browser test), chromium-driver
#              (chromedriver: the explorer's page driven through WebDriver),
#              slurm-wlm + munge (a single-node Slurm on localhost: the corpus job-array test)
#   intel    : what scripts/setup-vendors.sh needs to build Mesa's Intel noop drm-shim from
#              the release's Mesa source (meson, ninja, mako, yaml, bison, flex, libdrm/expat/zlib
#              headers, dpkg-dev for `apt-get source`)
#   compilers: what scripts/build-compilers.sh needs to build Mesa 25.0.7's Turnip, panvk,
#              OpenGL ES drivers and drm-shims (meson itself is pip-installed into the cache:
#              Debian 12's is too old), glslang-tools (Turnip's internal shaders)
#   gl       : the OpenGL route of `shadelab isa` (nouveau, r600): Mesa's EGL and DRI drivers,
#              spirv-cross (SPIR-V to GLSL)
#   debian13 : debootstrap, for scripts/check-debian13.sh (a Debian 13 root to test in)
# A package counts as present when dpkg says it is installed or, for one installed another way,
# when the file or command it provides is there (the loader, an ICD naming lavapipe, the static
# libraries, ...).
# SHADELAB_NO_INSTALL=1: install nothing; look for the files only, list what is missing as a
# warning and exit 0 (the build or the tests then fail on their own if something essential lacks).
# Usage: scripts/install-deps.sh [run|build|test|intel|compilers|gl|debian13]...
#                                                             (default: run build test)
#        scripts/install-deps.sh --release   prints bookworm, trixie or the distribution's
#                                            codename (the suite the other scripts fetch from)
set -euo pipefail

# The distribution and release: ID, VERSION_ID, VERSION_CODENAME, ID_LIKE of os-release.
os_field() {
  local f
  for f in /etc/os-release /usr/lib/os-release; do
    [ -r "$f" ] && { (. "$f" && eval "echo \"\${$1:-}\""); return; }
  done
  echo ""
}
os_id=$(os_field ID)
os_version=$(os_field VERSION_ID)
case "$os_id:$os_version" in
  debian:12) release=bookworm ;;
  debian:13) release=trixie ;;
  *) release="" ;;
esac
if [ "${1:-}" = "--release" ]; then
  echo "${release:-$(os_field VERSION_CODENAME)}"
  exit 0
fi

want=()
for set in "${@:-run build test}"; do
  for s in $set; do
    case "$s" in
      run) want+=(libvulkan1 mesa-vulkan-drivers) ;;
      build) want+=(gcc g++ make git pkg-config ca-certificates libshaderc-dev glslang-dev
                    spirv-tools) ;;
      test) want+=(vulkan-validationlayers spirv-tools chromium chromium-driver slurm-wlm munge) ;;
      intel) want+=(meson ninja-build python3-mako python3-yaml bison flex libdrm-dev
                    libexpat1-dev zlib1g-dev pkg-config dpkg-dev xz-utils ca-certificates) ;;
      compilers) want+=(ninja-build python3-mako python3-yaml python3-pip bison flex gcc g++
                        libdrm-dev libexpat1-dev zlib1g-dev pkg-config dpkg-dev xz-utils
                        glslang-tools ca-certificates
                        llvm-15-dev libclang-15-dev libclang-cpp15-dev libclc-15
                        libllvmspirvlib-15-dev) ;;
      gl) want+=(libegl1 libegl-mesa0 libgl1-mesa-dri spirv-cross ca-certificates) ;;
      debian13) want+=(debootstrap ca-certificates) ;;
      *) echo "install-deps: unknown set '$s' (expected run, build, test, intel, compilers, gl or debian13)" >&2; exit 2 ;;
    esac
  done
done

# What each package is for (the message on a distribution this script does not know).
role() {
  case "$1" in
    libvulkan1) echo "the Vulkan loader (libvulkan.so.1)" ;;
    mesa-vulkan-drivers) echo "Mesa's Vulkan drivers: lavapipe, RADV, ANV (their ICD manifests)" ;;
    gcc | g++) echo "a C/C++ compiler and linker (cargo links with cc; the C++ runtime)" ;;
    make | git | meson | bison | flex | debootstrap | spirv-cross) echo "the $1 command" ;;
    ninja-build) echo "the ninja command" ;;
    pkg-config) echo "pkg-config (finds the shader compiler's libraries)" ;;
    libshaderc-dev) echo "shaderc's static library libshaderc_combined.a and headers" ;;
    glslang-dev) echo "glslang's static libraries (libglslang.a ...)" ;;
    glslang-tools) echo "glslangValidator" ;;
    spirv-tools) echo "SPIRV-Tools' static libraries and spirv-val" ;;
    vulkan-validationlayers) echo "the Khronos validation layer (VK_LAYER_KHRONOS_validation)" ;;
    chromium) echo "a headless Chromium (chromium on PATH)" ;;
    chromium-driver) echo "chromedriver (WebDriver for Chromium)" ;;
    slurm-wlm) echo "Slurm's slurmctld, slurmd, sbatch" ;;
    munge) echo "munged (Slurm's authentication)" ;;
    python3-mako | python3-yaml | python3-pip) echo "Python's ${1#python3-} module" ;;
    libdrm-dev | libexpat1-dev | zlib1g-dev) echo "the headers and pkg-config file of ${1%-dev}" ;;
    dpkg-dev) echo "dpkg-source (unpacks Debian's Mesa source)" ;;
    xz-utils) echo "xz" ;;
    ca-certificates) echo "TLS certificates" ;;
    libegl1 | libegl-mesa0) echo "EGL (libEGL.so.1, Mesa's EGL vendor library)" ;;
    libgl1-mesa-dri) echo "Mesa's OpenGL drivers (nouveau, r600)" ;;
    *) echo "$1" ;;
  esac
}

# The library folders of the loader's cache and of the C compiler.
lib_dirs() {
  { ldconfig -p 2>/dev/null | sed -n 's|.* => \(.*\)/[^/]*$|\1|p'
    cc -print-search-dirs 2>/dev/null | sed -n 's/^libraries: =//p' | tr ':' '\n'
  } | sort -u
}
has_lib() { # a file named $1 in a library folder
  local d
  for d in $(lib_dirs); do [ -e "$d/$1" ] && return 0; done
  return 1
}
has_cmd() { command -v "$1" >/dev/null 2>&1; }
has_py() { # Debian's python3 first (a pyenv shim's python lacks Debian's modules)
  /usr/bin/python3 -c "import $1" >/dev/null 2>&1 || python3 -c "import $1" >/dev/null 2>&1
}
has_pc() { has_cmd pkg-config && pkg-config --exists "$1"; }
# A JSON manifest under a Vulkan folder ($1: icd.d or explicit_layer.d) holding $2: the
# loader's standard folders and the XDG ones.
has_manifest() {
  local d f
  for d in /etc/vulkan /usr/local/share/vulkan /usr/share/vulkan \
    ${XDG_DATA_DIRS:+$(echo "$XDG_DATA_DIRS" | tr ':' '\n' | sed 's|$|/vulkan|')}; do
    for f in "$d/$1"/*.json; do
      [ -f "$f" ] && grep -q "$2" "$f" && return 0
    done
  done
  return 1
}

# Whether what package $1 provides is there, by its files alone.
present() {
  case "$1" in
    libvulkan1) has_lib libvulkan.so.1 ;;
    mesa-vulkan-drivers) has_manifest icd.d libvulkan_lvp ;;
    gcc) has_cmd cc ;;
    g++) has_cmd c++ ;;
    make | git | bison | flex | debootstrap | spirv-cross | meson | xz) has_cmd "$1" ;;
    xz-utils) has_cmd xz ;;
    ninja-build) has_cmd ninja ;;
    pkg-config) has_cmd pkg-config ;;
    libshaderc-dev) has_pc shaderc || has_lib libshaderc_combined.a ;;
    glslang-dev) has_lib libglslang.a ;;
    glslang-tools) has_cmd glslangValidator ;;
    spirv-tools) has_cmd spirv-val && has_lib libSPIRV-Tools.a ;;
    vulkan-validationlayers) has_manifest explicit_layer.d VK_LAYER_KHRONOS_validation ;;
    chromium) has_cmd chromium || has_cmd chromium-browser ;;
    chromium-driver) has_cmd chromedriver ;;
    slurm-wlm) has_cmd slurmctld && has_cmd slurmd ;;
    munge) has_cmd munged ;;
    python3-mako) has_py mako ;;
    python3-yaml) has_py yaml ;;
    python3-pip) python3 -m pip --version >/dev/null 2>&1 ;;
    libdrm-dev) has_pc libdrm ;;
    libexpat1-dev) has_pc expat ;;
    zlib1g-dev) has_pc zlib ;;
    dpkg-dev) has_cmd dpkg-source ;;
    ca-certificates) [ -s /etc/ssl/certs/ca-certificates.crt ] ;;
    libegl1) has_lib libEGL.so.1 ;;
    libegl-mesa0) has_lib libEGL_mesa.so.0 ;;
    libgl1-mesa-dri) has_lib dri/nouveau_dri.so || has_lib dri/r600_dri.so ;;
    *) return 1 ;;
  esac
}

installed() {
  has_cmd dpkg-query &&
    dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"
}

missing=()
for p in "${want[@]}"; do
  if [ "${SHADELAB_NO_INSTALL:-0}" = 1 ]; then
    present "$p" && continue
  else
    { installed "$p" || present "$p"; } && continue
  fi
  case " ${missing[*]-} " in *" $p "*) ;; *) missing+=("$p") ;; esac
done
[ ${#missing[@]} -eq 0 ] && exit 0

list_roles() {
  local p
  for p in "${missing[@]}"; do echo "install-deps:   $p: $(role "$p")" >&2; done
}
if [ "${SHADELAB_NO_INSTALL:-0}" = 1 ]; then
  echo "install-deps: WARNING: SHADELAB_NO_INSTALL=1, nothing installed; not found (Debian's name: what it provides):" >&2
  list_roles
  exit 0
fi
if [ -z "$release" ]; then
  name="$(os_field PRETTY_NAME)"
  echo "install-deps: ${name:-this system} is not Debian 12 or 13, where shadelab was checked; it needs (Debian's package name: what it provides):" >&2
  list_roles
  case " $(os_field ID_LIKE) $os_id " in
    *" debian "*) has_cmd apt-get && echo "install-deps: trying Debian's names with apt-get" >&2 ;;
    *) echo "install-deps: install your distribution's packages for these roles, then run again with SHADELAB_NO_INSTALL=1" >&2
       exit 2 ;;
  esac
fi
if ! has_cmd apt-get; then
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: no apt-get here; install the equivalents of these Debian packages by hand (or SHADELAB_NO_INSTALL=1 to go on)" >&2
  list_roles
  exit 2
fi
if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif has_cmd sudo && sudo -n true 2>/dev/null; then
  sudo=(sudo -n)
elif has_cmd sudo && [ -t 0 ]; then
  sudo=(sudo)
else
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: not root and no usable sudo; run as root: apt-get install ${missing[*]} (or SHADELAB_NO_INSTALL=1 to go on without)" >&2
  exit 2
fi
echo "install-deps: installing ${missing[*]}" >&2
# One apt at a time on this machine: two apt-get runs at once (two checkouts building side by
# side) break each other's update. flock waits for the other one to finish.
if has_cmd flock; then
  exec 9>"${TMPDIR:-/tmp}/shadelab-apt.lock"
  flock 9
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
