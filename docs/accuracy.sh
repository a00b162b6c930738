#!/usr/bin/env bash
# Reproduces the accuracy table of the README (docs/accuracy.md): both paper presets, protocol
# variants and the OpenCV peers on ../shared/datasets/kitti2015, pooled over all pixels.
# Usage: bash docs/accuracy.sh [path/to/parallax]         (prints a Markdown table)
#        bash docs/accuracy.sh knobs [path/to/parallax]   (the knob table: one sweep with its peers)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
MODE=table
if [ "${1:-}" = knobs ]; then MODE=knobs; shift; fi
P="${1:-build/release/explore/parallax}"
D=../shared/datasets/kitti2015
if [ "$MODE" = knobs ]; then
  # configs/sweeps/knobs-vs-opencv.yaml: each knob alone and in combination, and OpenCV's two
  # modes, measured by one command on the same 30 crops; then one Markdown row per design.
  T=$(mktemp -d)
  "$P" sweep configs/sweeps/knobs-vs-opencv.yaml --dataset $D --db "$T/knobs.db" >&2
  "$P" report --db "$T/knobs.db" --csv "$T/knobs.csv" >&2
  python3 - "$T/knobs.csv" "$T/knobs.db" <<'PY'
import csv, json, sqlite3, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| design (over the seed) | paths | passes | density % | correct < 3 px % | D1 filled % | mean abs error px | BRAM_18K | LUT | fps |")
print("|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    name = r["name"]
    what = name[name.find("[") + 1:name.rfind("]")] if "[" in name else "seed (ruf2018-census)"
    print("| %s | %s | %d | %.1f | %.2f | %.1f | %.3f | %d | %s | %.1f |" % (what, r["paths"], 2 if r["paths"] == "8" else 1,
          float(r["density_pct"]), float(r["correct_3px_pct"]), float(r["d1_all_filled_pct"]),
          float(r.get("mean_abs_error_px", "nan") or "nan"),
          float(r["bram18k"]), format(int(float(r["lut"])), ","), float(r["fps"])))
for config, metrics in sqlite3.connect(sys.argv[2]).execute("SELECT config, metrics FROM results WHERE status = 'peer'"):
    m = json.loads(metrics)
    print("| %s (same frames) | 8 | full frame | %.1f | %.2f | %.1f | %.3f | - | - | - |" % (config.split("\n")[0].split(": ")[1],
          m["density_pct"], m["correct_3px_pct"], m["d1_all_filled_pct"], m.get("mean_abs_error_px", float("nan"))))
PY
  rm -rf "$T"
  exit 0
fi
row() {  # label, then the command's arguments
  local label="$1"; shift
  "$P" "$@" --json 2>/dev/null | python3 -c '
import json, sys
j = json.load(sys.stdin)
print("| %s | %d | %.1f | %.1f | %.1f | %.1f | %.1f |" % (sys.argv[1], j["frames"], j["density_pct"], j["density_gt_pct"],
      j["correct_3px_pct"], j["d1_all_pct"], j["d1_all_filled_pct"]))' "$label"
}
echo "| design / protocol | frames | density % | density (GT px) % | correct < 3 px % | D1 (valid) % | D1 filled % |"
echo "|---|---|---|---|---|---|---|"
for cost in census sad; do
  C=configs/ruf2018-$cost.yaml
  row "ruf2018-$cost, noc (preset)" eval --config $C --dataset $D
  row "ruf2018-$cost, occ (preset)" eval --config $C --dataset $D --gt occ
  row "ruf2018-$cost, noc, lr_tolerance 0" eval --config $C --dataset $D --set lr_tolerance=0
  row "ruf2018-$cost, noc, median off" eval --config $C --dataset $D --set median=0
  row "ruf2018-$cost, noc, lr_tolerance 0, median off" eval --config $C --dataset $D --set lr_tolerance=0 --set median=0
  row "ruf2018-$cost, noc, D = 128" eval --config $C --dataset $D --set disparities=128 --set parallel_units=8
  row "ruf2018-$cost, noc, whole image matched, then cropped" eval --config $C --dataset $D --context full
  row "ruf2018-$cost, noc, 8 paths" eval --config $C --dataset $D --set paths=8
  row "ruf2018-$cost, noc, 5 paths (180 on reversed rows, one pass)" eval --config $C --dataset $D --set paths=5
  for u in 5 10 20; do
    row "ruf2018-$cost, noc, uniqueness_pct $u" eval --config $C --dataset $D --set uniqueness_pct=$u
  done
done
C=configs/ruf2018-census.yaml
for cw in "sparse 5x5" "symmetric 5x5" "full 9x7" "sparse 9x7" "symmetric 9x7" "sparse 9x9"; do
  set -- $cw
  row "ruf2018-census, noc, census $1 $2" eval --config $C --dataset $D --set census=$1 --set window=$2
done
row "frontier-census (configs/frontier-census.yaml), noc" eval --config configs/frontier-census.yaml --dataset $D
for b in opencv-hh4 opencv-sgbm; do
  row "$b (D 64, block 5, P1 200, P2 800), noc" baseline $b --dataset $D
  row "$b, occ" baseline $b --dataset $D --gt occ
done
