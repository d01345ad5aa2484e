#!/usr/bin/env bash
# The glows' tiers, error against cost (docs/FOG.md "Glows at scale"): runs the bench, then charts each
# budget's median error against the glow evaluations per pixel of the smooth image, one series per air.
#   bash tools/glow_tiers_chart.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
"$build/bench/atmo_glow_tiers_error_cost" --csv docs/measurements/glow_tiers_error_cost.csv |
  tee docs/measurements/glow_tiers_error_cost.txt
# Sorted by cost within each air (the chart joins a series' points in file order); a short label each.
python3 - <<'PY'
import csv
rows = list(csv.DictReader(open("docs/measurements/glow_tiers_error_cost.csv")))
rows = [r for r in rows if float(r["median"]) > 0 and float(r["evaluations_per_pixel"]) > 0]
rows.sort(key=lambda r: (r["air"], float(r["evaluations_per_pixel"]), float(r["median"])))
with open("docs/measurements/glow_tiers_chart.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["air", "label", "evaluations_per_pixel", "median_error"])
    for r in rows:
        label = "all exact" if r["budget"].startswith("every") else f'{r["exact"]}/{r["merged"]}/{r["opens"]}'
        w.writerow([r["air"], label, r["evaluations_per_pixel"], r["median"]])
PY
"$build/tools/chart/atmo-chart" --csv docs/measurements/glow_tiers_chart.csv --out docs/images/glow_tiers_error_cost.png \
  --x evaluations_per_pixel --y median_error --group air --label label --logx --logy \
  --title "Glows' tiers: median error against every light's glow vs. cost (15 000 lights)" \
  --xlabel "glow evaluations per pixel of the smooth image (exact/merged/opens)" --ylabel "median relative error" \
  --hline 0.1 --hline-label "10 %" --legend top-right
