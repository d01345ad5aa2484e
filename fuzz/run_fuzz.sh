#!/usr/bin/env bash
# run_fuzz.sh FUZZER CORPUS ARTIFACTS SECONDS — the CTest test of one fuzz
# target: fuzzes a temporary copy of the seed corpus (the repository is never
# written) for SECONDS, with a 10 s limit per input and 2 GiB of memory.
# SECONDS 0 replays the corpus once and mutates nothing (fuzz_vdb: see
# fuzz/CMakeLists.txt).
# libFuzzer exits non-zero on a crash, a sanitizer report, a leak, a timeout
# or running out of memory; the failing input is written to ARTIFACTS/.
# The suite's runs start from one seed, ATMO_FUZZ_SEED (default 1), so a CI
# run replays what a run here explored first; ATMO_FUZZ_SEED=0 draws one.
set -euo pipefail
fuzzer=$1 corpus=$2 artifacts=$3 seconds=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$corpus"/. "$work"/
mkdir -p "$artifacts"
if [ "$seconds" = 0 ]; then
  echo "[fuzz] $(basename "$fuzzer"): replaying $(ls "$corpus" | wc -l) seeds (no mutation); failing inputs go to $artifacts/"
  limit=(-runs=0)
else
  echo "[fuzz] $(basename "$fuzzer"): $(ls "$corpus" | wc -l) seeds, ${seconds} s; failing inputs go to $artifacts/"
  limit=(-max_total_time="$seconds" -seed="${ATMO_FUZZ_SEED:-1}")
fi
"$fuzzer" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
          -artifact_prefix="$artifacts/" "$work"
