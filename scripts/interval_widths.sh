#!/usr/bin/env bash
# How wide a report's lavapipe intervals are (not a test): per scene, the median over its
# methods of the 95 % interval's width relative to the median, for bench's paired frame-time
# ratio to phong_exact and, where measured, the isolated cost's. Two reports at the same size
# and runs can be compared this way (issue 43: "intervals no wider than today's").
# Usage: scripts/interval_widths.sh REPORT_DIR [REPORT_DIR ...]
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: scripts/interval_widths.sh REPORT_DIR [REPORT_DIR ...]" >&2; exit 2; }
python3 - "$@" <<'PY'
import glob, json, statistics, sys

def width(lo, mid, hi):
    return (hi - lo) / mid if mid and mid > 0 else float("inf")

for base in sys.argv[1:]:
    files = sorted(glob.glob(f"{base}/scenes/*/bench/bench.json"))
    if not files:
        sys.exit(f"{base}: no scenes/*/bench/bench.json (a report's folder?)")
    print(base)
    for f in files:
        rows = json.load(open(f))["methods"]
        frame = [width(r["ratio_ci95_low"], r["ratio_median"], r["ratio_ci95_high"])
                 for r in rows if r.get("ratio_rounds", 0) > 0]
        iso = [width(i["ci95_low"], i["median"], i["ci95_high"])
               for r in rows if (i := r.get("isolated_ratio_to_phong_exact"))]
        line = f"  {f.split('/')[-3]}: frame time {100 * statistics.median(frame):.1f} % ({len(frame)} methods)"
        if iso:
            line += f", isolated cost {100 * statistics.median(iso):.1f} % ({len(iso)} methods)"
        print(line)
PY
