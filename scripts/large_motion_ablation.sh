#!/bin/sh
# The large-motion ablation of docs/datasets.md (issue 19): trifocal_line_ekf through the image
# front end on the KITTI excerpt, once per front-end setting (flow seed, pyramid depth,
# descriptor re-matching), each evaluated against the ground truth. Writes OUT/NAME.{json,tum,
# csv,eval} per setting and OUT/ablation.md, the table (new reference pairs after the first,
# frames with detection, live lines per frame, fraction of the previous frame's lines kept by
# the flow, lines re-matched, ATE, RPE, lost frames).
#
#   scripts/large_motion_ablation.sh [--build DIR] DATA_DIR OUT_DIR
#   (DATA_DIR: the KITTI folder, e.g. ../shared/data/kitti_excerpt_1)
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build"
if [ "${1:-}" = "--build" ]; then
  build=$(cd "$2" && pwd)
  shift 2
fi
[ $# -eq 2 ] || { echo "usage: large_motion_ablation.sh [--build DIR] DATA_DIR OUT_DIR" >&2; exit 2; }
data=$1
out=$2
mkdir -p "$out"

run() {
  name=$1
  echo "$2" > "$out/$name.json"
  "$build/bin/track_images" --path "$data" --method trifocal_line_ekf --config "$out/$name.json" \
    --output "$out/$name.tum" --log "$out/$name.csv" 2> "$out/$name.err" > /dev/null
  "$build/bin/evaluate" --gt "$data/poses.txt" --gt-format kitti --est "$out/$name.tum" > "$out/$name.eval"
}

run plain_lk '{"motion": {"seed": "none", "rematch_below_fraction": 0}}'
run plain_lk_5_levels '{"motion": {"seed": "none", "rematch_below_fraction": 0, "unpredicted_pyramid_levels": 5}}'
run plain_lk_1_level '{"motion": {"seed": "none", "rematch_below_fraction": 0, "unpredicted_pyramid_levels": 1}, "tracking": {"pyramid_levels": 1}}'
run image_seed '{"motion": {"seed": "image", "rematch_below_fraction": 0}}'
run prediction_seed '{"motion": {"rematch_below_fraction": 0}}'
run prediction_seed_1_level '{"motion": {"rematch_below_fraction": 0, "unpredicted_pyramid_levels": 1}, "tracking": {"pyramid_levels": 1}}'
run prediction_seed_1_level_5_unpredicted '{"motion": {"rematch_below_fraction": 0, "unpredicted_pyramid_levels": 5}, "tracking": {"pyramid_levels": 1}}'
run default '{}'
run prediction_rematch_80 '{"motion": {"rematch_below_fraction": 0.8}}'
run plain_lk_rematch_80 '{"motion": {"seed": "none", "rematch_below_fraction": 0.8}}'

python3 - "$out" plain_lk plain_lk_5_levels plain_lk_1_level image_seed prediction_seed prediction_seed_1_level \
  prediction_seed_1_level_5_unpredicted default prediction_rematch_80 plain_lk_rematch_80 <<'PY'
import csv, json, os, sys
out, names = sys.argv[1], sys.argv[2:]
def metric(lines, key):
    return float(next(l.split()[3] for l in lines if l.startswith(key)))
table = ["| setting | front-end options | new references | detection frames | lines per frame | kept by the flow | re-matched | ATE (m) | RPE (m, deg) | lost |",
         "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
for n in names:
    rows = list(csv.DictReader(open(os.path.join(out, n + '.csv'))))
    new_refs = sum(r['status'] == 'new_reference' for r in rows) - 1
    lost = sum(r['status'] == 'lost' for r in rows)
    detections = sum(int(r['detected']) for r in rows)
    lines = sum(int(r['lines']) for r in rows) / len(rows)
    tracked = sum(int(r['lines']) - int(r['added']) - int(r['rematched']) for r in rows[1:])
    before = tracked + sum(int(r['lost']) for r in rows[1:])
    rematched = sum(int(r['rematched']) for r in rows)
    ev = open(os.path.join(out, n + '.eval')).read().splitlines()
    options = json.dumps(json.load(open(os.path.join(out, n + '.json'))), separators=(',', ':'))
    table.append(f"| {n} | `{options}` | {new_refs} | {detections} | {lines:.1f} | {100 * tracked / before:.1f} % | {rematched} | "
                 f"{metric(ev, 'ATE translation'):.3f} | {metric(ev, 'RPE translation'):.3f}, {metric(ev, 'RPE rotation'):.3f} | {lost} |")
open(os.path.join(out, 'ablation.md'), 'w').write("\n".join(table) + "\n")
print("\n".join(table))
PY
