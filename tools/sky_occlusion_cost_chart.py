#!/usr/bin/env python3
"""The spheres sweep of atmo_sky_occlusion_bench as a chart's CSV: the host's ground shaded through
atmo_sky_occlusion.glsl (16 objects), one series per mode (default: bounce + hybrid; no bounce; optimal
linear), as a ratio to the LUT sky + aerial-perspective pair drawn in the same frames, by spheres an object;
and the same ground shaded from the SH9 alone (no occlusion) for scale; every pixel through the include
reading the plugin's image (ATMO_PASS_SKY_OCCLUSION_IMAGE at 8 x 8 and 16 x 16 blocks, the image pass + the
host pass). With --png it draws the chart too. With --error-png, the image's error against cost at 16 x 32.

  build/bench/atmo_sky_occlusion_bench --frames 3 --csv docs/measurements/sky_occlusion_bench_1280x720.csv
  python3 tools/sky_occlusion_cost_chart.py docs/measurements/sky_occlusion_bench_1280x720.csv \\
      docs/measurements/sky_occlusion_cost_by_spheres.csv \\
      --png docs/images/sky_occlusion_cost_by_spheres.png --chart build/tools/chart/atmo-chart
which runs
  build/tools/chart/atmo-chart --csv docs/measurements/sky_occlusion_cost_by_spheres.csv \\
      --out docs/images/sky_occlusion_cost_by_spheres.png --x spheres --y ratio --group series --logx --logy \\
      --hline 1 --hline-label "the pair (sky + aerial perspective)"
and with --error-csv docs/measurements/sky_occlusion_image_error_cost.csv
--error-png docs/images/sky_occlusion_image_error_cost.png, the 16 x 32 row's image modes: p95 of the sky's
and the bounce's error against the include at every pixel (fraction of the open sky) by cost.
"""
import argparse
import csv
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bench_csv")
    ap.add_argument("chart_csv")
    ap.add_argument("--png", help="draw the chart into this PNG (needs --chart)")
    ap.add_argument("--chart", default="build/tools/chart/atmo-chart", help="the atmo-chart executable")
    ap.add_argument("--renderer", default="llvmpipe", help="the GL renderer the bench ran on (the title's)")
    ap.add_argument("--error-csv", help="write the image's error-versus-cost chart CSV here")
    ap.add_argument("--error-png", help="and draw it into this PNG")
    a = ap.parse_args()

    rows = [r for r in csv.DictReader(open(a.bench_csv)) if r["sweep"] == "spheres"]
    if not rows:
        sys.exit("sky_occlusion_chart: no rows of the spheres sweep in " + a.bench_csv)
    with open(a.chart_csv, "w") as out:
        out.write("# from %s (tools/sky_occlusion_cost_chart.py): 16 objects, the host's ground through "
                  "atmo_sky_occlusion.glsl, cost as a ratio to the LUT sky + aerial-perspective pair\n" % a.bench_csv)
        out.write("spheres,ratio,series\n")
        plain = {}
        for r in sorted(rows, key=lambda r: (r["mode"], int(r["spheres_per_object"]))):
            k = int(r["spheres_per_object"])
            out.write("%d,%.4f,include (%s)\n" % (k, float(r["ratio_to_pair"]), r["mode"]))
            plain.setdefault(k, []).append(float(r["plain_ms"]) / float(r["pair_ms"]))
        for r in sorted(rows, key=lambda r: int(r["spheres_per_object"])):  # the plugin's pass over the ground
            if "pass_quarter_ratio_to_pair" not in r or r["mode"] not in ("default", "no bounce"):
                continue
            k = int(r["spheres_per_object"])
            out.write("%d,%.4f,ATMO_PASS_SKY_OCCLUSION 1/4 (%s)\n" % (k, float(r["pass_quarter_ratio_to_pair"]), r["mode"]))
            out.write("%d,%.4f,ATMO_PASS_SKY_OCCLUSION 1/8 (%s)\n" % (k, float(r["pass_eighth_ratio_to_pair"]), r["mode"]))
            if "image_eighth_ratio_to_pair" in r:
                out.write("%d,%.4f,include via the image 8x8 (%s)\n" % (k, float(r["image_eighth_ratio_to_pair"]), r["mode"]))
                out.write("%d,%.4f,include via the image 16x16 (%s)\n" % (k, float(r["image_sixteenth_ratio_to_pair"]), r["mode"]))
        for k in sorted(plain):  # the host's pass without occlusion, the mean over the modes' frames
            out.write("%d,%.4f,host pass from the SH9 alone\n" % (k, sum(plain[k]) / len(plain[k])))
    status = 0
    if a.error_csv:
        status = error_chart(a, rows)
    if a.png:
        cmd = [a.chart, "--csv", a.chart_csv, "--out", a.png, "--x", "spheres", "--y", "ratio", "--group", "series",
               "--logx", "--logy", "--hline", "1", "--hline-label", "the pair (sky + aerial perspective)",
               "--title", "Sky occlusion: the ground through the include or the pass, 16 objects, 1280x720, %s" % a.renderer,
               "--xlabel", "spheres an object", "--ylabel", "cost / the pair's (wall time to glFinish)",
               "--legend", "top-left"]
        return subprocess.call(cmd) or status
    return status


def error_chart(a, rows):
    """The image's p95 error against its cost, 16 objects x 32 spheres, default mode."""
    row = [r for r in rows if int(r["spheres_per_object"]) == 32 and r["mode"] == "default"]
    if not row or "image_eighth_ratio_to_pair" not in row[0]:
        sys.exit("sky_occlusion_chart: no image columns for 16 x 32 in " + a.bench_csv)
    r = row[0]
    with open(a.error_csv, "w") as out:
        out.write("# from %s (tools/sky_occlusion_cost_chart.py): 16 objects x 32 spheres, every pixel through the "
                  "include reading the image, cost / the pair against the p95 error of the sky + bounce (vs the include "
                  "at every pixel, fraction of the open sky)\n" % a.bench_csv)
        out.write("cost,error,series,label\n")
        for name, blocks in (("quarter", "4x4"), ("eighth", "8x8"), ("sixteenth", "16x16")):
            out.write("%.4f,%.5f,the image (sky + bounce),%s blocks\n"
                      % (float(r["image_%s_ratio_to_pair" % name]), float(r["image_%s_sky_error_p95" % name]), blocks))
    if not a.error_png:
        return 0
    cmd = [a.chart, "--csv", a.error_csv, "--out", a.error_png, "--x", "cost", "--y", "error", "--group", "series",
           "--label", "label", "--logx", "--logy",
           "--title", "Every pixel through the include's image: error against cost, 16 x 32, 1280x720, %s" % a.renderer,
           "--xlabel", "cost / the pair's (image pass + host pass)", "--ylabel",
           "p95 error of sky + bounce vs the include at every pixel (of the open sky)", "--legend", "top-right"]
    return subprocess.call(cmd)


if __name__ == "__main__":
    sys.exit(main())
