#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file test.sh
# @brief Set up, build, and pass every test: unit + GPU tests (lavapipe, validation layer on),
#        then under AddressSanitizer + UBSan the CPU tests with the fuzz smoke runs and a fast
#        subset of the GPU and OpenXR tests (label asan-gpu).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc)
"$root/scripts/build.sh"

echo "== tests: unit + gpu (build/) =="
ctest --test-dir "$root/build" --output-on-failure -j"$jobs"

echo "== tests: unit, fuzz smoke runs and asan-gpu under AddressSanitizer + UBSan (build-asan/) =="
# XRSC_GPU=ON: the sanitizers also cover the renderer, the program and the OpenXR runtime
# (linked against clang's shared sanitizer runtime, see CMakeLists.txt).
cmake -S "$root" -B "$root/build-asan" -DXRSC_GPU=ON -DXRSC_SANITIZE=ON -DXRSC_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$root/build-asan" -j"$jobs"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$root/build-asan" --output-on-failure -j"$jobs" -L unit
# The GPU tests of the subset run on lavapipe with the validation layer, as in build/; the
# OpenXR loader's own leak is suppressed by the tests' LSAN_OPTIONS (tests/xr/lsan.supp).
ctest --test-dir "$root/build-asan" --output-on-failure -j"$jobs" -L asan-gpu
