# Sourced by scripts/setup-vendors.sh and scripts/build-compilers.sh (not run on its own).
# apt_private NAME ARGS...: apt-get with a private configuration under $cache/apt/NAME (the
# caller sets $cache): its own sources, lists and archives; the system's apt state is only read
# (dpkg's status), never written.
apt_private() {
  local name=$1
  shift
  local dir="$cache/apt/$name"
  mkdir -p "$dir/lists/partial" "$dir/archives/partial" "$dir/parts"
  apt-get -q -o Dir::Etc::SourceList="$dir/sources.list" -o Dir::Etc::SourceParts="$dir/parts" \
    -o Dir::State::Lists="$dir/lists" -o Dir::Cache="$dir" -o Dir::Cache::archives="$dir/archives" \
    -o Dir::Cache::pkgcache= -o Dir::Cache::srcpkgcache= -o APT::Sandbox::User=root \
    -o Debug::NoLocking=true "$@"
}
