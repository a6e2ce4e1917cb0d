#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file test.sh
# @brief Set up, build, and pass every test: unit + GPU tests (lavapipe, validation layer on),
#        then the CPU tests again under AddressSanitizer + UBSan with the fuzz smoke runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc)
"$root/scripts/build.sh"

echo "== tests: unit + gpu (build/) =="
ctest --test-dir "$root/build" --output-on-failure -j"$jobs"

echo "== tests: unit under AddressSanitizer + UBSan, fuzz smoke runs (build-asan/) =="
cmake -S "$root" -B "$root/build-asan" -DXRSC_GPU=OFF -DXRSC_SANITIZE=ON -DXRSC_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$root/build-asan" -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$root/build-asan" --output-on-failure -j"$jobs" -L unit
