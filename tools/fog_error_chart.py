#!/usr/bin/env python3
"""The fog glow's airlight error against table size (docs/measurements/fog_airlight_error.md): runs
atmo_fog_error_chart (bench/fog_error_chart.cpp) unless --no-run, then draws its CSV with atmo-chart.

  tools/fog_error_chart.py --build build \\
      --csv docs/measurements/fog_airlight_error.csv \\
      --png docs/images/fog_airlight_error.png

Chart (g = 0.85, the plugin's default fog; --g 0 draws the isotropic rows): relative error against the
reference quadrature (y, percent, log) against the airlight table's size (x, log), on the same 630
scenes: median and worst of the plugin's stable form and of the paper's F form, each with fp32 and fp16
texels, and of the plugin's whole lit-surface pixel (surface term + airlight, fp32); a dashed line for
OpenGL exponential fog, which does not depend on a table: 100 % on airlight pixels (it has no glow), its
lit-surface median and worst in the legend entry (the median is within a factor 1.2 of 100 %, which the
log axis would not separate). Values above --clip (default 1e5 %) are drawn at the clip (the CSV keeps
them).
"""
import argparse
import os
import subprocess
import sys

from measurement_csv import rows, run_logged
import tempfile


def fmt(v):
    return f"{v:.3g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build",
                    help="build tree with bench/atmo_fog_error_chart and tools/chart/atmo-chart")
    ap.add_argument("--csv", required=True)
    ap.add_argument("--png", required=True)
    ap.add_argument("--log", help="copy of the tool's standard output")
    ap.add_argument("--g", default="0.85", help="phase asymmetry charted (0.85 or 0.00)")
    ap.add_argument("--clip", type=float, default=1e5, help="largest error drawn (percent)")
    ap.add_argument("--no-run", action="store_true", help="only draw the chart from an existing CSV")
    a = ap.parse_args()

    if not a.no_run:
        cmd = [os.path.join(a.build, "bench", "atmo_fog_error_chart"), "--csv", a.csv]
        code = run_logged(cmd, a.log)
        if code:
            return code

    data = [r for r in rows(a.csv) if f"{float(r['g']):.2f}" == f"{float(a.g):.2f}"]
    if not data:
        print(f"fog_error_chart: no rows with g = {a.g} in {a.csv}", file=sys.stderr)
        return 2
    sizes = sorted({int(r["size"]) for r in data if int(r["size"]) > 0})
    clipped = False

    def y(v):
        nonlocal clipped
        v = float(v)
        if v > a.clip:
            clipped = True
            return a.clip
        return max(v, 1e-4)

    series = []  # (name, [(size, value)])

    def table_series(form, precision, label):
        by_size = {int(r["size"]): r for r in data if r["form"] == form and r["precision"] == precision}
        for stat, col in (("median", "median_pct"), ("worst", "worst_pct")):
            series.append((f"{label} {precision}: {stat}", [(s, y(by_size[s][col])) for s in sizes if s in by_size]))

    # Order = colours and markers (atmo-chart's palette of 9 repeats): the one series that shares a colour
    # (the paper's fp16 worst, last) lies far from the first (the stable form's fp32 median).
    table_series("stable form (plugin)", "fp32", "stable form")
    table_series("stable form (plugin)", "fp16", "stable form")
    table_series("paper F form", "fp32", "paper F form")
    paper16 = []
    table_series("paper F form", "fp16", "paper F form")
    paper16.append(series.pop())  # its worst goes last
    table_series("plugin: lit-surface pixels", "fp32", "plugin model (whole lit-surface pixel)")
    series.extend(paper16)
    # OpenGL exp fog: 100 % on airlight pixels (no glow); on lit-surface pixels its median is within a factor
    # 1.2 of that, which a log axis cannot separate: one dashed line, both figures in its legend entry.
    gl_air = [r for r in data if r["form"] == "OpenGL exp fog: airlight pixels"]
    gl_lit = [r for r in data if r["form"] == "OpenGL exp fog: lit-surface pixels"]
    hline = float(gl_air[0]["median_pct"]) if gl_air else 100.0
    hline_label = f"OpenGL exp fog: airlight pixels {fmt(hline)} %"
    if gl_lit:
        r = gl_lit[0]
        hline_label += (f"; lit-surface pixels median {fmt(float(r['median_pct']))} %"
                        f" (worst {fmt(float(r['worst_pct']))} %)")

    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        chart_csv = f.name
        f.write("series,size,error_pct\n")
        for name, points in series:
            for s, v in points:
                f.write(f"{name.replace(',', ';')},{s},{v:.6g}\n")  # atmo-chart has no quoting
    chart = os.path.join(a.build, "tools", "chart", "atmo-chart")
    title = f"Fog glow (airlight) vs the reference quadrature: 630 scenes, T 0.01-20, gamma 0-180 deg, g = {a.g}"
    ylabel = "relative error (%, log scale)"
    if clipped:
        ylabel += f"; values above {fmt(a.clip)} % drawn at {fmt(a.clip)} %"
    try:
        return subprocess.call([chart, "--csv", chart_csv, "--out", a.png, "--x", "size", "--y", "error_pct",
                                "--group", "series", "--logx", "--logy", "--legend", "bottom-left",
                                "--title", title,
                                "--xlabel", "airlight table size (texels per side, log scale)",
                                "--ylabel", ylabel, "--width", "1500", "--height", "1300",
                                "--hline", fmt(hline), "--hline-label", hline_label])
    finally:
        os.unlink(chart_csv)


if __name__ == "__main__":
    sys.exit(main())
