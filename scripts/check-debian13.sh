#!/usr/bin/env bash
# `make demo` and `make test` in a minimal Debian 13 (trixie) root, as a newcomer on Debian 13
# would run them: the check that shadelab works beyond the Debian 12 it is developed on.
#
# As root: debootstrap (installed through scripts/install-deps.sh debian13) makes a minbase
# trixie root from the mirror apt already uses, once, under
#   ${XDG_CACHE_HOME:-~/.cache}/shadelab/debian13/root
# (a second run reuses it, with the packages, cargo's registry, the vendor set-up and the
# build's target/ left there by the first). The repository's committed HEAD is cloned in
# (/root/shadelab), the host's Rust toolchain (`rustc --print sysroot`) is bound in read-only
# (Debian 13 packages rustc 1.85; Cargo.toml asks 1.86), and the models folder
# (SHADELAB_MODELS, else ../shared/models) is bound in read-only at /root/shared/models.
# Inside: scripts/install-deps.sh build (a minbase root has no make nor cc), then `make demo`,
# then `make test`, each logged under debian13/logs/. Everything mounted is unmounted on exit
# and on interruption.
# Exit status: 0 when both pass, 1 when either fails, 2 when the root cannot be made.
# Environment: SHADELAB_DEBIAN13_FRESH=1 starts from a new root; SHADELAB_REQUIRE_* variables
# are passed in (as .ci/run sets them), but for SHADELAB_REQUIRE_CONVERTERS: the glTF converter
# needs node and npm, which a minbase root lacks and make test does not install (its test says
# SKIPPED there; it runs on the host).
# Usage: scripts/check-debian13.sh              make demo, then make test
#        scripts/check-debian13.sh --run CMD    CMD alone in the clone (e.g. one test), logged
#                                               as run.log and printed
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/.." && pwd)"
say() { echo "check-debian13: $*" >&2; }
die() { say "$*"; exit 2; }

[ "$(id -u)" -eq 0 ] || die "must run as root (debootstrap, mount, chroot): sudo $0"
base="${XDG_CACHE_HOME:-$HOME/.cache}/shadelab/debian13"
root="$base/root"
logs="$base/logs"
mkdir -p "$logs"
t0=$(date +%s)
elapsed() { echo "$(($(date +%s) - t0)) s"; }

"$here/install-deps.sh" debian13 || die "could not install debootstrap (scripts/install-deps.sh debian13)"

# The mirror apt already uses: the first Debian URI of the system's sources.
mirror=$(
  { grep -h '^URIs:' /etc/apt/sources.list.d/*.sources 2>/dev/null | awk '{print $2}'
    grep -h '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null |
      sed 's/\[[^]]*\]//' | awk '{print $2}'
  } | grep -v -e security -e backports | head -n 1
) || true
mirror=${mirror:-http://deb.debian.org/debian}

sysroot=$(rustc --print sysroot 2>/dev/null) ||
  die "no Rust toolchain on the host (rustc --print sysroot failed): install rustup's stable"
models="${SHADELAB_MODELS:-$repo/../shared/models}"

mounted=()
child=""
cleanup() {
  local i
  # What runs in the root first (its own session: setsid below), then the mounts.
  if [ -n "$child" ]; then
    kill -TERM -- "-$child" 2>/dev/null || true
    sleep 2
    kill -KILL -- "-$child" 2>/dev/null || true
    child=""
  fi
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    umount "${mounted[$i]}" 2>/dev/null || umount -l "${mounted[$i]}" 2>/dev/null ||
      say "could not unmount ${mounted[$i]}"
  done
  mounted=()
}
trap cleanup EXIT
trap 'say "interrupted"; cleanup; exit 130' INT TERM
mnt() { # mnt TARGET ARGS...: mount and remember
  local target=$1
  shift
  mkdir -p "$target"
  mount "$@" "$target"
  mounted+=("$target")
}

if [ "${SHADELAB_DEBIAN13_FRESH:-0}" = 1 ] && [ -d "$root" ]; then
  say "removing the old root (SHADELAB_DEBIAN13_FRESH=1)"
  grep -q " $root" /proc/mounts && die "$root still has mounts: unmount them first"
  rm -rf "$root"
fi
if [ ! -f "$root/.shadelab-root" ]; then
  say "debootstrap --variant=minbase trixie from $mirror"
  rm -rf "$root.partial"
  debootstrap --variant=minbase trixie "$root.partial" "$mirror" >"$logs/debootstrap.log" 2>&1 ||
    { tail -n 20 "$logs/debootstrap.log" >&2; die "debootstrap failed (log: $logs/debootstrap.log)"; }
  mkdir -p "$root.partial/root/.cargo"
  # cargo's registry as the host has it: the crates are not fetched again.
  [ -d "$HOME/.cargo/registry" ] && cp -a "$HOME/.cargo/registry" "$root.partial/root/.cargo/"
  touch "$root.partial/.shadelab-root"
  mv "$root.partial" "$root"
  say "root made ($(elapsed))"
fi

# The repository's committed HEAD, cloned in (target/ and the cache stay from the last run).
src="$root/root/shadelab"
rev=$(git -C "$repo" rev-parse HEAD)
if [ ! -d "$src/.git" ]; then
  git clone -q --no-hardlinks "$repo" "$src"
fi
git -C "$src" fetch -q "$repo" "$rev"
git -C "$src" checkout -q --force "$rev"
git -C "$src" clean -q -fdx -e target
say "clone at $(git -C "$src" rev-parse --short=12 HEAD)"

mnt "$root/proc" -t proc proc
mnt "$root/sys" -t sysfs sysfs
# Slurm 24.11's slurmd needs the cgroup filesystem a booted Debian 13 has ("No filesystem
# mounted on /sys/fs/cgroup" otherwise).
[ -d /sys/fs/cgroup ] && mnt "$root/sys/fs/cgroup" --bind /sys/fs/cgroup
mnt "$root/dev" --bind /dev
mnt "$root/dev/pts" --bind /dev/pts
mnt "$root/dev/shm" -t tmpfs tmpfs
mnt "$root/tmp" -t tmpfs tmpfs
mnt "$root/opt/rust" --bind "$sysroot"
mount -o remount,bind,ro "$root/opt/rust"
if [ -d "$models" ]; then
  mnt "$root/root/shared/models" --bind "$models"
  mount -o remount,bind,ro "$root/root/shared/models"
else
  say "no models folder at $models: the models tests will say SKIPPED"
fi
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
# The host's trust store, for cargo's downloads in the root: a network that reaches the
# registries through a proxy with its own certificate authority (the host trusts it; a minbase
# root's ca-certificates does not) would otherwise refuse every crate.
host_ca="${SSL_CERT_FILE:-/etc/ssl/certs/ca-certificates.crt}"
ca_env=()
if [ -f "$host_ca" ]; then
  # a minbase root has no /etc/ssl until ca-certificates is installed in it
  mkdir -p "$root/etc/ssl"
  cp "$host_ca" "$root/etc/ssl/host-ca-certificates.crt"
  ca_env=(CARGO_HTTP_CAINFO=/etc/ssl/host-ca-certificates.crt
    SSL_CERT_FILE=/etc/ssl/host-ca-certificates.crt CURL_CA_BUNDLE=/etc/ssl/host-ca-certificates.crt)
fi

# in_root NAME COMMAND: runs COMMAND in the root with a clean environment, logged.
in_root() {
  local name=$1 cmd=$2 env=(HOME=/root LANG=C.UTF-8 TERM=dumb CARGO_HOME=/root/.cargo
    PATH=/opt/rust/bin:/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin)
  local v
  for v in $(env | sed -n 's/^\(SHADELAB_REQUIRE_[A-Z_]*\)=..*/\1/p'); do
    [ "$v" = SHADELAB_REQUIRE_CONVERTERS ] || env+=("$v=${!v}")
  done
  [ -d "$models" ] && env+=(SHADELAB_MODELS=/root/shared/models)
  env+=("${ca_env[@]}")
  local s=$(date +%s) status=0
  say "$name ..."
  setsid chroot "$root" /usr/bin/env -i "${env[@]}" /bin/bash -c "cd /root/shadelab && $cmd" \
    >"$logs/$name.log" 2>&1 &
  child=$!
  wait "$child" || status=$?
  child=""
  times+=("$name: $([ $status -eq 0 ] && echo PASS || echo "FAIL (exit $status)") in $(($(date +%s) - s)) s (log: $logs/$name.log)")
  say "${times[-1]}"
  [ $status -eq 0 ] || tail -n 30 "$logs/$name.log" | sed 's/^/check-debian13:   /' >&2
  return $status
}

times=()
if [ "${1:-}" = "--run" ]; then
  shift
  status=0
  in_root run "$*" || status=$?
  cat "$logs/run.log"
  exit $status
fi
demo=0 tests=0
in_root deps "scripts/install-deps.sh build" || die "the build packages did not install"
in_root demo "make demo" || demo=1
in_root test "make test" || tests=1
say "Debian 13 ($(chroot "$root" cat /etc/debian_version)), shadelab $(git -C "$src" rev-parse --short=12 HEAD), $(elapsed) in all:"
for t in "${times[@]}"; do say "  $t"; done
grep -h "SKIPPED" "$logs/test.log" 2>/dev/null | sed 's/^/check-debian13:   /' >&2 || true
[ $demo -eq 0 ] && [ $tests -eq 0 ]
