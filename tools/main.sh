#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what is missing, build,
# and render the default scenario headless (EXR + PNG + per-pass timings).
#   bash tools/main.sh            render config/scenarios/noon_clear.json into out/
#   bash tools/main.sh --window   open the sample host window instead (needs a display)
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j"$(nproc)"
if [ "${1:-}" = "--window" ]; then
  exec build/samples/sample_host/atmo-sample-host
fi
build/tools/atmo/atmo render config/scenarios/noon_clear.json --out out --repeat 3
echo "[atmo] default scenario written to out/noon_clear_main.exr and out/noon_clear_main.png"
