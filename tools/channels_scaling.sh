#!/usr/bin/env bash
# channels_scaling.sh [BUILD_DIR] — atmo-channels' wall time per frame on this machine (loopback MPI) for
# 1, 2, 3 and 4 processes, written to docs/measurements/channels_scaling.csv (docs/MULTI_CHANNEL.md,
# "Scaling"). Two series:
#   one_channel_per_process  N = P channels, one per process (more channels, more machines)
#   four_channels            N = 4 channels shared by P processes (the same picture on more machines)
# Each run flies FRAMES frames (default 12) of config/scenarios/flights/channels_flight.json at SIZE (default
# 320x180) without writing images; the figure is rank 0's median wall time per frame, barrier to barrier, over
# frames 1..FRAMES-1 (atmo-channels' CSV). A benchmark, not a test: run it on an idle machine.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
frames=${FRAMES:-12}
size=${SIZE:-320x180}
scenario=config/scenarios/flights/channels_flight.json
exe=$build/samples/channels/atmo-channels
[ -x "$exe" ] || { echo "channels_scaling: no $exe (build the atmo-channels target)" >&2; exit 2; }
mpi=(mpirun --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
out=docs/measurements/channels_scaling.csv
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)
echo "series,processes,channels,frames,size,median_ms_per_frame,mean_ms_per_frame,cores,renderer,cpu" > "$tmp/out.csv"
median_mean() {  # the frame_ms column of an atmo-channels CSV, frames 1.., as "median,mean"
  python3 - "$1" <<'PY'
import csv, statistics, sys
ms = [float(r["frame_ms"]) for r in csv.DictReader(open(sys.argv[1])) if int(r["frame"]) > 0]
print(f"{statistics.median(ms):.1f},{statistics.mean(ms):.1f}")
PY
}
for series in one_channel_per_process four_channels; do
  for p in 1 2 3 4; do
    n=$p
    [ "$series" = four_channels ] && n=4
    dir="$tmp/${series}_$p"
    log="$dir.log"
    echo "channels_scaling: $series: $p process(es), $n channel(s), $frames frames at $size" >&2
    "${mpi[@]}" -np "$p" "$exe" --scenario "$scenario" --views "$n" --frames "$frames" --size "$size" --no-images \
      --out "$dir" > "$log" 2>&1 || { echo "channels_scaling: the run failed (its checks or an error); see below" >&2; tail -20 "$log" >&2; }
    [ -f "$dir/channels.csv" ] || { echo "channels_scaling: no CSV from that run" >&2; exit 1; }
    renderer=$(sed -n 's/^atmo-channels \[rank 0\]: \([^;]*\);.*/\1/p' "$log" | head -1)
    echo "$series,$p,$n,$frames,$size,$(median_mean "$dir/channels.csv"),$(nproc),\"$renderer\",\"$cpu\"" >> "$tmp/out.csv"
  done
done
mkdir -p "$(dirname "$out")"
cp "$tmp/out.csv" "$out"
cat "$out"
