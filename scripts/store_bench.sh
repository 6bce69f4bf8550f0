#!/usr/bin/env bash
# The compile store's figures (docs/figures.md "compile store" rows): with an empty store of its
# own (SHADELAB_STORE in a temporary folder, so the user's store is neither read nor changed),
#   1. `shadelab isa --out I` in float32 and float16, each cold (empty store) then warm;
#   2. `shadelab tune --mesh M` twice on the same mesh (default scenes/torus.obj), the second
#      into another folder, then on another mesh (OTHER, default scenes/sphere_coarse.obj: its
#      candidates are new programs, its baselines come from the store), then on M again with
#      the store off (`--no-cache`: what a first run costs without the store);
#   3. `shadelab report --scenes scenes --out R` twice (the second with the store the first
#      filled; `make demo`'s report), unless --no-report, each followed by where its time went
#      (the seconds of each step of its progress lines, summed over the scenes).
# Mesa's own shader cache (lavapipe's compiled shaders) is a folder of the run too, empty at the
# start (MESA_SHADER_CACHE_DIR), so a first run is cold in both caches.
# Per step: wall seconds (the command alone) and the load average before it (the machine is
# shared: state the load with the figure). Exits 1 when a warm run compiled any family
# (isa.json's `source` is not from_store everywhere).
# A route rebuilt between two runs (`make compilers` re-installing its files) is another
# compiler identity: its families are compiled again, and the script says which.
# Usage: scripts/store_bench.sh [--no-isa] [--no-tune] [--no-report] [MESH [OTHER]]
#   (builds the release binary first)
set -euo pipefail
cd "$(dirname "$0")/.."
report=1
isa=1
tune=1
while [[ "${1:-}" == --no-* ]]; do
  case "$1" in
    --no-report) report=0 ;;
    --no-isa) isa=0 ;;
    --no-tune) tune=0 ;;
    *) echo "unknown option $1"; exit 2 ;;
  esac
  shift
done
mesh="${1:-scenes/torus.obj}"
other="${2:-scenes/sphere_coarse.obj}"
cargo build --release --locked --quiet
bin=target/release/shadelab
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export SHADELAB_STORE="$tmp/store"
export MESA_SHADER_CACHE_DIR="$tmp/mesa"
unset SHADELAB_NO_CACHE
echo "$(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); store $SHADELAB_STORE"

# timed NAME CMD...: runs CMD (stdout and stderr to $tmp/NAME.log), prints its wall time and
# the load average before it.
timed() {
  local name=$1; shift
  local load; load=$(cut -d' ' -f1-3 /proc/loadavg)
  local start end
  start=$(date +%s.%N)
  "$@" > "$tmp/$name.log" 2>&1 || { echo "$name: FAILED"; tail -5 "$tmp/$name.log"; exit 1; }
  end=$(date +%s.%N)
  printf '%-22s %7.2f s wall   (load average before: %s)\n' "$name" "$(echo "$end - $start" | bc)" "$load"
}

# all_from_store DIR: every compiled family of DIR/isa.json was read from the store.
all_from_store() {
  python3 - "$1/isa.json" <<'PY'
import json, sys
fams = [f for f in json.load(open(sys.argv[1]))["families"] if f["supported"]]
bad = [f["id"] for f in fams if f.get("source") != "from_store"]
print(f"  {len(fams)} families compiled, {len(fams) - len(bad)} from the store"
      + (f"; compiled again: {', '.join(bad)}" if bad else ""))
sys.exit(1 if bad else 0)
PY
}

for p in f32 f16; do
  [[ $isa == 1 ]] || break
  timed "isa-$p-cold" $bin isa --precision $p --out "$tmp/isa-$p-cold"
  timed "isa-$p-warm" $bin isa --precision $p --out "$tmp/isa-$p-warm"
  all_from_store "$tmp/isa-$p-warm" || { echo "isa $p warm compiled a family"; exit 1; }
done
if [[ $tune == 1 ]]; then
  timed tune-first $bin tune --mesh "$mesh" --error-budget 1/255 --out "$tmp/tune1"
  timed tune-second $bin tune --mesh "$mesh" --error-budget 1/255 --out "$tmp/tune2"
  timed tune-other-mesh $bin tune --mesh "$other" --error-budget 1/255 --out "$tmp/tune3"
  timed tune-no-store $bin tune --mesh "$mesh" --error-budget 1/255 --out "$tmp/tune4" --no-cache
fi

# steps NAME: the seconds of each step of report NAME's progress lines (`report: [N s] scene:
# step`), summed over its scenes, from its log.
steps() {
  python3 - "$tmp/$1.log" <<'PY'
import re, sys
marks = [(int(m[1]), m[2]) for m in re.finditer(r"^report: \[(\d+) s\] (?:[^:\n]+: )?(.+)$",
                                              open(sys.argv[1]).read(), re.M)]
total = {}
for (t, step), (t_next, _) in zip(marks, marks[1:]):
    total[step] = total.get(step, 0) + t_next - t
print("  " + ", ".join(f"{step} {s} s" for step, s in sorted(total.items(), key=lambda x: -x[1])))
PY
}
if [[ $report == 1 ]]; then
  timed report-first $bin report --scenes scenes --out "$tmp/report1" -v
  steps report-first
  timed report-second $bin report --scenes scenes --out "$tmp/report2" -v
  steps report-second
  all_from_store "$tmp/report2/isa" || { echo "the second report compiled a family"; exit 1; }
fi
echo "store: $($bin cache | tail -1)"
