#!/usr/bin/env bash
# README's test command: install what is missing, build, run the whole suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/deps.sh
bash .ci/build.sh
ctest --test-dir build --output-on-failure -j2
