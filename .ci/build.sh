#!/usr/bin/env bash
# Configures and builds pgt (Release, warnings as errors) into build/ with two jobs.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPGT_WERROR=ON
cmake --build build -j2
