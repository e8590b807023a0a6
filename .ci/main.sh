#!/usr/bin/env bash
# README's main command: install what is missing, build, render the bundled default scene,
# run its default study and write the study's report. Results land in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/deps.sh
bash .ci/build.sh
./build/src/pgt render scenes/default.json --out out/default
/usr/bin/python3 analysis/plot_summary.py out/default/summary.json --out out/default/summary.png
./build/src/pgt sweep scenes/default.json --out out/study --fresh  # recomputed: 1-2 min
echo "frame: out/default/ (frame.exr, summary.json, *_error.png, summary.png)"
echo "report: out/study/report.md"
