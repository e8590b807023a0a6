#!/usr/bin/env bash
# Builds (Release) and runs the Google Benchmark targets; results on stdout.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/deps.sh
bash .ci/build.sh
./build/tests/bench/pgt_bench --benchmark_min_time=0.5 "$@"
