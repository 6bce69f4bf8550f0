#!/usr/bin/env bash
# Where the throughput models change an answer of the static cost (not a test): per family of an
# isa.json, the methods whose timed draw's fragment program is cheaper than phong_exact's by the
# family's ranking statistic but not by the figure each vendor ranked by before its throughput
# model, or the other way: NVIDIA, Arm and Broadcom an instruction count (`inst`); Intel brw's
# latency estimate (`cycle_count`); Adreno ir3's instructions with their latency NOPs plus its
# (ss) and (sy) stall estimates.
# Usage: scripts/ranking_changes.sh ISA_DIR   (from `shadelab isa --out ISA_DIR`)
set -euo pipefail
dir=${1:?usage: scripts/ranking_changes.sh ISA_DIR}
[ -f "$dir/isa.json" ] || { echo "ranking_changes: no $dir/isa.json" >&2; exit 2; }
python3 - "$dir/isa.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
before = {
    "nvidia": ("inst", lambda s: s["inst"]),
    "arm": ("inst", lambda s: s["inst"]),
    "broadcom": ("inst", lambda s: s["inst"]),
    "intel": ("cycle_count", lambda s: s["cycle_count"]),
    "qualcomm": ("instructions+stalls", lambda s: s["instruction_count"]
                 + s["estimated_cycles_stalled_on_ss"] + s["estimated_cycles_stalled_on_sy"]),
}
key = {f["family"]: f["ranking"]["key"] for f in d["families"] if f["supported"]}
rows = {}
for r in d["results"]:
    if r["stage"] == "fragment" and r["kind"] == "draw":
        rows[(r["family"], r["method"])] = r
for f in d["families"]:
    fam = f["family"]
    vendor = fam.split(":")[0]
    if not f["supported"] or vendor not in before or (fam, "phong_exact") not in rows:
        continue
    name, old = before[vendor]
    exact = rows[(fam, "phong_exact")]
    for (rf, method), r in rows.items():
        if rf != fam:
            continue
        a = old(r["statistics"]) / old(exact["statistics"])
        b = r["ratio_to_phong_exact"].get(key[fam])
        if b is None or (a < 1) == (b < 1):
            continue
        print(f"{fam} {method}: {name} {a:.3f} -> {key[fam]} {b:.3f} (bound: {r.get('bound_unit')})")
PY
