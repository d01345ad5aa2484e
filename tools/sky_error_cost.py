#!/usr/bin/env python3
"""Joins the sky accuracy CSV (build/bench/atmo_sky_accuracy) with the GPU
benchmark's JSON (build/bench/atmo_gpu_bench --benchmark_format=json) into one
error-vs-cost table per tier and setting, and draws it with atmo-chart.

  tools/sky_error_cost.py --accuracy docs/measurements/sky_accuracy_40km.csv \
      --bench docs/measurements/gpu_bench_llvmpipe.json \
      --csv docs/measurements/sky_error_cost.csv --png docs/images/sky_error_cost.png

Error (charted): the mean PSNR over the issue's five views (sky), or over the
three aerial views (aerial volume vs the per-pixel march). Cost: median wall
time to glFinish of sky + aerial perspective at 1280x720 (half sky, half
geometry), in the same benchmark run as the trivial passes it is compared with.
"""
import argparse
import csv
import json
import subprocess
import sys
from collections import defaultdict


def bench_medians(path):
    with open(path) as f:
        data = json.load(f)
    out = {}
    for b in data["benchmarks"]:
        # Medians of repetitions; a run without repetitions has only iterations.
        name = b["run_name"].split("/min_time")[0]
        if b.get("aggregate_name") == "median" or (b.get("run_type") == "iteration" and name not in out):
            out[name] = float(b["real_time"])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--accuracy", required=True)
    ap.add_argument("--bench", required=True)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--png", required=True)
    ap.add_argument("--chart-tool", default="build/tools/chart/atmo-chart")
    a = ap.parse_args()

    psnr = defaultdict(list)
    with open(a.accuracy) as f:
        for row in csv.DictReader(f):
            # The analytic tier's setting is its cross-fade weight, which differs per view: one row for it.
            setting = "cross-faded" if row["tier"] == "analytic" else row["setting"]
            psnr[(row["tier"], setting)].append(float(row["psnr_db"]))
    cost = bench_medians(a.bench)
    # (tier as charted, accuracy key, benchmark name)
    sizes = [("96x54", "16^3", 0), ("192x108", "32^3", 1), ("384x216", "64^3", 2)]
    rows = []
    for sky, volume, i in sizes:
        rows.append(("LUT tier (tables cached)", sky + " + " + volume, ("lut", sky), f"BM_Lut_SkyAndAerial/{i}"))
        rows.append(("LUT tier (tables rebuilt every frame)", sky + " + " + volume, ("lut", sky),
                     f"BM_Lut_SkyAndAerial_Rebuild/{i}"))
        rows.append(("aerial volume vs march (aerial pass)", volume, ("aerial_volume", volume), f"BM_Lut_Aerial/{i}"))
    rows.append(("march tier (32 steps/pixel)", "32 steps", ("march", "32steps"), "BM_March_SkyAndAerial"))
    analytic = [k for k in psnr if k[0] == "analytic"]
    for key in analytic:
        rows.append(("analytic tier (Preetham + LUT hand-over)", key[1], key, "BM_Analytic_SkyAndAerial"))
    missing = [r for r in rows if r[2] not in psnr or r[3] not in cost]
    if missing:
        for r in missing:
            print(f"sky_error_cost: no data for {r[2]} / {r[3]}", file=sys.stderr)
        return 2
    with open(a.csv, "w") as f:
        f.write("# error: worst PSNR over the views (dB); cost: median ms per frame at 1280x720 on the bench's renderer\n")
        f.write("tier,setting,cost_ms,psnr_worst_db,psnr_mean_db\n")
        for tier, setting, key, bench in rows:
            values = psnr[key]
            f.write(f"{tier},{setting},{cost[bench]:.3f},{min(values):.2f},{sum(values) / len(values):.2f}\n")
    trivial = cost.get("BM_TrivialTwoFetchPass")
    title = "Sky + aerial perspective: error vs cost (1280x720, llvmpipe)"
    if trivial:
        title += f"; trivial 2-fetch pass {trivial:.1f} ms"
    return subprocess.call([a.chart_tool, "--csv", a.csv, "--out", a.png, "--x", "cost_ms", "--y", "psnr_mean_db", "--legend", "top-right",
                            "--group", "tier", "--label", "setting", "--logx", "--title", title,
                            "--xlabel", "cost per frame (ms, log scale)",
                            "--ylabel", "mean PSNR over the views (dB; sky vs spectral reference, volume vs march)",
                            "--hline", "40", "--hline-label", "40 dB target", "--width", "1400", "--height", "900"])


if __name__ == "__main__":
    sys.exit(main())
