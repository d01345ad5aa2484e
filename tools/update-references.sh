#!/usr/bin/env bash
# Re-renders every scenario and replaces its regression reference PNGs in
# config/scenarios/references/. Run it only after a deliberate change to the
# model, and look at every new image (git diff shows which changed) before
# committing: the references catch unintended changes, they do not prove
# physics (the reference integrator and the luminance checks do that).
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mktemp -d)
mkdir -p config/scenarios/references
for scenario in config/scenarios/*.json; do
  stem=$(basename "$scenario" .json)
  build/tools/atmo/atmo render "$scenario" --out "$out" >/dev/null || true  # a failing reference check is expected here
  for png in "$out/${stem}"_*.png; do
    camera=${png#"$out/${stem}_"}; camera=${camera%.png}
    cameras=$(ls "$out/${stem}"_*.png | wc -l)
    if [ "$cameras" -eq 1 ]; then cp "$png" "config/scenarios/references/${stem}.png"
    else cp "$png" "config/scenarios/references/${stem}_${camera}.png"; fi
  done
done
rm -rf "$out"
ls -la config/scenarios/references
