#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, build-fuzz/) and runs each for
# ${FUZZ_SECONDS:-60} s from its committed corpus (tests/fuzz/corpus_*). New inputs go to a
# scratch directory, so the committed corpus stays as it is; a crash, leak or sanitizer
# report fails the run and leaves the input in build-fuzz/ (crash-*, leak-*).
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/deps.sh
cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DPGT_FUZZ=ON -DPGT_BUILD_TESTS=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build-fuzz -j2 --target fuzz_scene fuzz_image fuzz_gltf
# Leaks inside Debian's libraries are suppressed by name (.ci/lsan.supp says which and why).
export LSAN_OPTIONS="suppressions=$PWD/.ci/lsan.supp:print_suppressions=0"
for target in scene image gltf; do
  scratch=$(mktemp -d)
  (cd build-fuzz && ./tests/fuzz/fuzz_$target "$scratch" "../tests/fuzz/corpus_$target" \
     -max_total_time="${FUZZ_SECONDS:-60}" -rss_limit_mb=4096 -timeout=30 -print_final_stats=1 \
     2>&1 | tail -15)
  rm -rf "$scratch"
done
echo "fuzz: fuzz_scene, fuzz_image and fuzz_gltf ran ${FUZZ_SECONDS:-60} s each without a finding"
