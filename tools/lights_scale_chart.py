#!/usr/bin/env python3
"""The town sweep of atmo_lights_scale_bench as a chart's CSV: each case's light passes and host surface
lighting as ratios to the LUT sky + aerial-perspective pair, by light count (docs/FOG.md "At scale").

  python3 tools/lights_scale_chart.py docs/measurements/lights_scale_bench_1280x720.csv \
      docs/measurements/lights_scale_by_count.csv
  build/tools/chart/atmo-chart --csv docs/measurements/lights_scale_by_count.csv \
      --out docs/images/lights_scale_by_count.png --x lights --y ratio --group series --logx --logy --hline 1
"""
import csv
import sys


def main(source, target):
    rows = list(csv.DictReader(open(source)))
    with open(target, "w") as out:
        out.write("# from %s (tools/lights_scale_chart.py): the town sweep, cost as a ratio to the LUT sky + "
                  "aerial-perspective pair\n" % source)
        out.write("lights,ratio,series\n")
        for r in rows:
            if not r["case"].startswith("town"):
                continue
            air = "fog" if "fog" in r["air"] else "clear night"
            out.write("%s,%.4f,light passes (%s)\n" % (r["lights"], max(float(r["light_x"]), 1e-3), air))
            out.write("%s,%.4f,host surfaces (%s)\n" % (r["lights"], float(r["host_x"]), air))
            # What the lights cost a frame in all: the 65 536 against 1 000 (<= 2x).
            out.write("%s,%.4f,all the lights (%s)\n" % (r["lights"], float(r["light_x"]) + float(r["host_x"]), air))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: lights_scale_chart.py BENCH_CSV CHART_CSV")
    main(sys.argv[1], sys.argv[2])
