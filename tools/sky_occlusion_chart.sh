#!/usr/bin/env bash
# Sky occlusion by spheres, error against cost (docs/SKY_OCCLUSION.md): runs the bench, then charts the
# error by SH order and exponential, error against CPU cost, and error by sphere count.
#   bash tools/sky_occlusion_chart.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
m=docs/measurements
"$build/bench/atmo_sky_occlusion_error_cost" --csv $m/sky_occlusion_error_cost.csv | tee $m/sky_occlusion_error_cost.txt
python3 - <<'PY'
import csv
rows = list(csv.DictReader(open("docs/measurements/sky_occlusion_error_cost.csv")))
conf = [r for r in rows if r["study"] == "configurations" and not r["method"].startswith("include")]
with open("docs/measurements/sky_occlusion_by_order.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["method", "label", "order", "median_error", "p90_error", "cpu_us"])
    for r in sorted(conf, key=lambda r: (r["method"], int(r["order"]))):
        w.writerow([r["method"], "order " + r["order"], r["order"], r["median"], r["p90"], r["cpu_us"]])
with open("docs/measurements/sky_occlusion_by_spheres.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["method", "label", "spheres", "median_error", "cpu_us"])
    for r in sorted([r for r in rows if r["study"] == "sphere count"], key=lambda r: (r["method"], int(r["spheres"]))):
        w.writerow([r["method"], r["spheres"], r["spheres"], r["median"], r["cpu_us"]])
PY
chart="$build/tools/chart/atmo-chart"
"$chart" --csv $m/sky_occlusion_by_order.csv --out docs/images/sky_occlusion_error_by_order.png \
  --x order --y p90_error --group method --label label \
  --title "Sky occlusion: 90th-percentile error against the ray tracer by SH order (38 receivers)" \
  --xlabel "SH order (bands)" --ylabel "|E - E_ref| / E_open" --hline 0.05 --hline-label "5 %" --legend top-right
"$chart" --csv $m/sky_occlusion_by_order.csv --out docs/images/sky_occlusion_error_cost.png \
  --x cpu_us --y p90_error --group method --label label --logx \
  --title "Sky occlusion: error against CPU cost per receiver (double study; the include is ~2 us)" \
  --xlabel "CPU microseconds per receiver (this machine)" --ylabel "90th-percentile |E - E_ref| / E_open" \
  --hline 0.05 --hline-label "5 %" --legend top-right
"$chart" --csv $m/sky_occlusion_by_spheres.csv --out docs/images/sky_occlusion_error_by_spheres.png \
  --x spheres --y median_error --group method --label label --logx \
  --title "Sky occlusion: median error by sphere count (a random cluster, order 4)" \
  --xlabel "spheres" --ylabel "median |E - E_ref| / E_open" --hline 0.05 --hline-label "5 %" --legend top-left
