#!/usr/bin/env bash
# Where the throughput models change an answer of the static cost (not a test): per family of an
# isa.json, the methods whose timed draw's fragment program is cheaper than phong_exact's by the
# family's ranking statistic but not by the instruction count it replaced, or the other way.
# Usage: scripts/ranking_changes.sh ISA_DIR   (from `shadelab isa --out ISA_DIR`)
set -euo pipefail
dir=${1:?usage: scripts/ranking_changes.sh ISA_DIR}
[ -f "$dir/isa.json" ] || { echo "ranking_changes: no $dir/isa.json" >&2; exit 2; }
python3 - "$dir/isa.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
# The instruction count each vendor ranked by before its throughput model.
count = {"nvidia": "inst", "qualcomm": "instruction_count", "arm": "inst", "broadcom": "inst"}
key = {f["family"]: f["ranking"]["key"] for f in d["families"] if f["supported"]}
for f in d["families"]:
    fam = f["family"]
    if not f["supported"] or fam.split(":")[0] not in count:
        continue
    old, new = count[fam.split(":")[0]], key[fam]
    for r in d["results"]:
        if r["family"] != fam or r["stage"] != "fragment" or r["kind"] != "draw":
            continue
        a, b = r["ratio_to_phong_exact"].get(old), r["ratio_to_phong_exact"].get(new)
        if a is None or b is None or (a < 1) == (b < 1):
            continue
        print(f"{fam} {r['method']}: {old} {a:.3f} -> {new} {b:.3f} (bound: {r.get('bound_unit')})")
PY
