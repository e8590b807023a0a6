#!/usr/bin/env bash
# README's main command: install what is missing, build, render the bundled default scene
# and plot its summary. Results land in out/default/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/deps.sh
bash .ci/build.sh
./build/src/pgt render scenes/default.json --out out/default
/usr/bin/python3 analysis/plot_summary.py out/default/summary.json --out out/default/summary.png
echo "results: out/default/ (frame.exr, summary.json, *_error.png, summary.png)"
