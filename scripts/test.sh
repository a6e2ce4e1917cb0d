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
# one slot more than cores: test_sweep_slurm and test_xr_conformance mostly wait (on slurm's
# daemons, on the conformance suite's runtime: 6-8 s CPU in 31-47 s), so the others run beside
# them (no test depends on time; tests/times.md)
ctest --test-dir "$root/build" --output-on-failure -j"$((jobs + 1))"

echo "== tests: unit, fuzz smoke runs and asan-gpu under AddressSanitizer + UBSan (build-asan/) =="
# XRSC_GPU=ON: the sanitizers also cover the renderer, the program and the OpenXR runtime
# (linked against clang's shared sanitizer runtime, see CMakeLists.txt).
cmake -S "$root" -B "$root/build-asan" -DXRSC_GPU=ON -DXRSC_SANITIZE=ON -DXRSC_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$root/build-asan" -j"$jobs"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$root/build-asan" --output-on-failure -j"$jobs" -L unit
# The GPU tests of the subset run on lavapipe with the validation layer (synchronization
# validation on), as in build/, under ASan and UBSan but without LeakSanitizer: Debian's
# validation layer 1.3.239 leaks about 96 KB in 360 allocations per process with
# synchronization validation on, and the Vulkan loader unloads it at vkDestroyInstance, so its
# frames cannot be symbolized or suppressed by name. Leaks of xrsc's own GPU path are checked
# by the runs below, which do not load the layer: direct and through OpenXR, with only the
# OpenXR loader's own leak suppressed (tests/xr/lsan.supp).
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 \
  ctest --test-dir "$root/build-asan" --output-on-failure -j"$jobs" -L asan-gpu
leak_out=$(mktemp -d)
for path in --direct ""; do
  LSAN_OPTIONS=suppressions=$root/tests/xr/lsan.supp "$root/build-asan/host_sim/xrsc" replay \
    $path --frames 3 --resolution 32x32 --write eyes,linear --out "$leak_out" --overwrite --quiet
  echo "asan-gpu: xrsc replay ${path:-through OpenXR} under LeakSanitizer: no leak"
done
rm -rf "$leak_out"
