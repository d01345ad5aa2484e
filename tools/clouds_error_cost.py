#!/usr/bin/env python3
"""The clouds' error against cost (docs/CLOUDS.md "Error against cost"): runs
atmo_clouds_error_cost (bench/clouds_error_cost.cpp) unless --no-run, then
draws its two CSV files with atmo-chart.

  tools/clouds_error_cost.py --build build-bench \\
      --csv docs/measurements/clouds_error_cost.csv \\
      --lighting-csv docs/measurements/clouds_lighting_error_cost.csv \\
      --png docs/images/clouds_error_cost.png \\
      --lighting-png docs/images/clouds_lighting_error_cost.png \\
      --log docs/measurements/clouds_error_cost.txt

Chart 1: PSNR of the displayed frame against the direct march at full
resolution and step 0.5 voxels (y) against the clouds pass's wall time per
frame (x, log), one series per sweep (impostor resolution, with and without
the texel rule; angle threshold on a moving path; the direct march at each
resolution divisor, labelled by step), a dashed line at the default
impostors' PSNR. Chart 2: the lighting approximations' mean relative
luminance error against the path tracer's stored references (y, all 16
views) against the CPU twin's march time per ray (x), one series per model
(single scattering, octaves alone, octaves + diffusion), labelled by the
octave count; the development / held-out split and the GL pass time are in
the CSV.
"""
import argparse
import os
import subprocess
import sys

from measurement_csv import rows, run_logged


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build-bench", help="build tree with atmo_clouds_error_cost and atmo-chart")
    ap.add_argument("--csv", required=True)
    ap.add_argument("--lighting-csv", required=True)
    ap.add_argument("--png", required=True)
    ap.add_argument("--lighting-png", required=True)
    ap.add_argument("--log", help="copy of the tool's standard output")
    ap.add_argument("--no-run", action="store_true", help="only draw the charts from existing CSV files")
    ap.add_argument("tool_args", nargs="*", help="passed to atmo_clouds_error_cost (after --)")
    a = ap.parse_args()

    if not a.no_run:
        cmd = [os.path.join(a.build, "bench", "atmo_clouds_error_cost"), "--csv", a.csv,
               "--lighting-csv", a.lighting_csv] + a.tool_args
        code = run_logged(cmd, a.log)
        if code:
            return code

    chart = os.path.join(a.build, "tools", "chart", "atmo-chart")
    main_rows = rows(a.csv)
    default = [r for r in main_rows if r["sweep"].startswith("impostors: texels (") and r["setting"] == "128"]
    args = [chart, "--csv", a.csv, "--out", a.png, "--x", "cost_ms", "--y", "psnr_db", "--group", "sweep",
            "--label", "label", "--logx", "--legend", "bottom-right",
            "--title", "Clouds: error vs cost (640x360, llvmpipe; reference: direct march, full res., step 0.5)",
            "--xlabel", "clouds pass per frame (ms, log scale; threshold path: mean, others: median)",
            "--ylabel", "PSNR of the frame vs the reference (dB, sRGB, peak 1)", "--width", "1400", "--height", "900"]
    if default:
        args += ["--hline", default[0]["psnr_db"], "--hline-label", "default impostors (128 texels, 0.5 deg)"]
    r = subprocess.call(args)
    if r:
        return r
    return subprocess.call([chart, "--csv", a.lighting_csv, "--out", a.lighting_png, "--x", "cpu_us_per_ray",
                            "--y", "all_views_pct", "--group", "series", "--label", "label", "--legend", "top-right",
                            "--title", "Cloud lighting vs the path tracer (16 views, stored references)",
                            "--xlabel", "CPU twin march per ray (microseconds; label: octave count)",
                            "--ylabel", "mean relative luminance error (%)", "--width", "1200", "--height", "800",
                            "--hline", "15", "--hline-label", "target 15 %"])

if __name__ == "__main__":
    sys.exit(main())
