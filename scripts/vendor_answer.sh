#!/usr/bin/env bash
# The answer per GPU vendor, from a report's answer.json and its scenes' compare summaries (not a
# test): for every vendor, the methods whose static cost is below phong_exact's on at least one of
# its families (with the ratio range over those families), the largest max |dI| of each such
# method on each scene, whether it meets 1/255 on any scene and on every scene, and the answer
# cells of that vendor's cost models. With f16, the float16 cost models judged on the float16
# compare (scenes/*/compare-f16).
# Usage: scripts/vendor_answer.sh REPORT_DIR [f32|f16]
#   REPORT_DIR from e.g. `shadelab report --scenes scenes --models DIR --runs 1 --out REPORT_DIR`
set -euo pipefail
dir=${1:?usage: scripts/vendor_answer.sh REPORT_DIR [f32|f16]}
precision=${2:-f32}
case "$precision" in f32 | f16) ;; *) echo "vendor_answer: precision is f32 or f16, not $precision" >&2; exit 2 ;; esac
[ -f "$dir/answer.json" ] || { echo "vendor_answer: no $dir/answer.json" >&2; exit 2; }
python3 - "$dir" "$precision" <<'PY'
import glob, json, os, sys
from collections import defaultdict

d, precision = sys.argv[1], sys.argv[2]
compare = "compare" if precision == "f32" else "compare-f16"
answer = json.load(open(os.path.join(d, "answer.json")))
errors = defaultdict(dict)  # method -> scene -> max |dI| (programs of `precision`)
nonfinite = defaultdict(int)
for path in sorted(glob.glob(os.path.join(d, "scenes", "*", compare, "summary.json"))):
    scene = path.split(os.sep)[-3]
    for m in json.load(open(path))["methods"]:
        errors[m["name"]][scene] = m["max_abs_error"]
        nonfinite[m["name"]] += m.get("non_finite_pixels", 0)
scenes = sorted({s for e in errors.values() for s in e})
limit = 1 / 255

static = [m for m in answer["cost_models"] if m["name"].startswith("isa:") and m["precision"] == precision]
if not static:
    sys.exit("vendor_answer: answer.json has no static (isa:) cost model; was isa set up?")
by_vendor = defaultdict(list)
for m in static:
    by_vendor[m["name"].split(":")[1]].append(m)

print(f"{precision} programs; scenes ({len(scenes)}): {', '.join(scenes)}")
for vendor, models in by_vendor.items():
    fams = [m["name"].split(":", 1)[1] for m in models]
    print(f"\n## {vendor}: {len(models)} families ({', '.join(fams)}); statistic: {models[0]['measure']['statistic']} ({models[0]['measure']['unit']})")
    cheaper = defaultdict(list)  # method -> ratios on families where cheaper
    for m in models:
        for f in m["figures"]:
            if f["method"] != "phong_exact" and f.get("ratio") is not None and f["ratio"] < 1:
                cheaper[f["method"]].append(f["ratio"])
    any_meets = False
    for meth in sorted(cheaper, key=lambda k: min(cheaper[k])):
        r = cheaper[meth]
        e = errors.get(meth, {})
        worst = max(e.values()) if e else float("nan")
        best_scene = min(e, key=e.get) if e else "-"
        meets = [s for s in scenes if e.get(s, float("inf")) <= limit and nonfinite[meth] == 0]
        any_meets |= bool(meets)
        print(f"- {meth}: ratio {min(r):.3f}-{max(r):.3f} on {len(r)}/{len(models)} families; "
              f"max |dI| {min(e.values()):.4g} ({best_scene}) to {worst:.4g}; "
              f"meets 1/255 on {len(meets)}/{len(scenes)} scenes{': ' + ', '.join(meets) if meets else ''}")
    print(f"- any cheaper method meeting 1/255 on some scene: {'yes' if any_meets else 'no'}")
    names = {m["name"] for m in models}
    answers = defaultdict(list)
    for c in answer["cells"]:
        if c["cost_model"] in names:
            a = c["answer"]["method"] if c.get("answer") else "none"
            answers[(c["budget"], "nothing cheaper than phong_exact" if c.get("nothing_cheaper") else a)].append(c["cost_model"])
    for (budget, what), ms in sorted(answers.items()):
        print(f"- answer at {budget}: {what} ({len(ms)}/{len(models)} families)")
PY
