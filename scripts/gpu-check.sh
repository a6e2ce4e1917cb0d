#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file gpu-check.sh
# @brief GPU readiness in one run: the GPU tests and `xrsc bench` at headset sizes with per-pass
#        GPU times (timestamp queries), written as one markdown report.
#
# Usage: scripts/gpu-check.sh [OUT_DIR]            (default out/gpu-check; report OUT_DIR/report.md)
#        scripts/gpu-check.sh --pack FILE.tar.gz    the build folder without objects, static
#          libraries and debug information (about 25 MB), to carry to the GPU machine and unpack
#          there with `mkdir -p build && tar xf FILE.tar.gz -C build`
# Runs from a build folder made elsewhere and copied here (no install step, no apt): when the
# paths compiled into the build (its source, build and shared folders, from CMakeCache.txt) do
# not exist on this machine, they are linked to where the copies are, if this user may.
# Environment (defaults in brackets):
#   GPU_CHECK_BUILD     the build folder                             [<repo>/build]
#   GPU_CHECK_DEVICE    device selector, as --device / XRSC_DEVICE    [gpu]
#   GPU_CHECK_SIZES     per-eye sizes benchmarked, space-separated   [1440x1600 2064x2208]
#   GPU_CHECK_SETTINGS  bench settings (xrsc bench --settings)       [samplecache;spp:spp=1;hashcache]
#   GPU_CHECK_FRAMES    frames per setting; GPU_CHECK_WARMUP frames left out of the means [20; 5]
#   GPU_CHECK_METRICS   1: also score one frame per setting (relMSE, SSIM...) against a
#                       GPU_CHECK_REF_SPP-spp reference [64]; the image metrics run on the CPU
#                       every frame (seconds per frame at these sizes), so by default the bench
#                       runs with --timing-only                     []
#   GPU_CHECK_TESTS     ctest -R regular expression of the tests run (empty: all `gpu` tests) []
#   GPU_CHECK_NO_TESTS  1: skip the tests                            []
#   GPU_CHECK_TEST_TIMEOUT, GPU_CHECK_BENCH_TIMEOUT  seconds for all tests / one bench size [200; 90]
# Exits 0 when every test passed and every bench size finished, else 1; the report is written
# either way. Sized for about 6 minutes on an H100.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${GPU_CHECK_BUILD:-$root/build}

# --pack: what the tests and the program need from the build, stripped of debug information
pack() { # FILE
  local file tmp
  file=$(realpath -m "$1")
  tmp=$(mktemp -d) || return 1
  (cd "$build" && tar cf - --exclude='*.o' --exclude='*.a' --exclude='*.d' --exclude=CMakeFiles \
    --exclude=Testing --exclude='*_out' .) | tar xf - -C "$tmp" &&
    find "$tmp" -type f \( -perm -u+x -o -name '*.so*' \) -exec strip --strip-debug {} + 2>/dev/null
  (cd "$tmp" && tar czf "$file" .)
  local rc=$?
  rm -rf "$tmp"
  ((rc == 0)) && echo "gpu-check: packed $build into $file ($(du -h "$file" | cut -f1))" >&2
  return $rc
}
if [[ ${1:-} == --pack ]]; then
  [[ -n ${2:-} ]] || { echo "usage: $0 --pack FILE.tar.gz" >&2; exit 2; }
  pack "$2"
  exit
fi

out=${1:-$root/out/gpu-check}
device=${GPU_CHECK_DEVICE:-gpu}
sizes=${GPU_CHECK_SIZES:-1440x1600 2064x2208}
settings=${GPU_CHECK_SETTINGS:-samplecache;spp:spp=1;hashcache}
frames=${GPU_CHECK_FRAMES:-20}
warmup=${GPU_CHECK_WARMUP:-5}
ref_spp=${GPU_CHECK_REF_SPP:-64}
test_timeout=${GPU_CHECK_TEST_TIMEOUT:-200}
bench_timeout=${GPU_CHECK_BENCH_TIMEOUT:-90}
exe=$build/host_sim/xrsc
report=$out/report.md
notes=()
status=0

mkdir -p "$out" || exit 1
export XRSC_DEVICE=$device

# The build's compiled-in paths (tests read scenes and fixtures through them; CTestTestfile
# names the programs by them): link each missing one to its copy here.
cache_value() { sed -n "s|^$1:[A-Z]*=||p" "$build/CMakeCache.txt" 2>/dev/null | head -n1; }
link_missing() { # ORIGINAL_PATH PATH_HERE
  local orig=$1 here=$2
  [[ -z $orig || -z $here || $orig == "$here" || -e $orig || ! -e $here ]] && return 0
  if mkdir -p "$(dirname "$orig")" 2>/dev/null && ln -s "$here" "$orig" 2>/dev/null; then
    notes+=("linked the build's path \`$orig\` to \`$here\`")
  else
    notes+=("the build's path \`$orig\` is missing and could not be linked to \`$here\`: tests that read fixtures by path fail")
  fi
}
orig_src=$(cache_value CMAKE_HOME_DIRECTORY)
orig_build=$(cache_value CMAKE_CACHEFILE_DIR)
orig_shared=$(cache_value XRSC_SHARED_DIR)
# compiled in lexically normalised (CMake's ABSOLUTE), e.g. /work/main/../shared -> /work/shared
[[ -n $orig_shared ]] && orig_shared=$(realpath -m -s "$orig_shared")
link_missing "$orig_src" "$root"
link_missing "$orig_build" "$build"
for s in "$root/shared" "$root/../shared"; do
  if [[ -d $s ]]; then
    link_missing "$orig_shared" "$(cd "$s" && pwd)"
    break
  fi
done

if [[ ! -x $exe ]]; then
  notes+=("no program at \`$exe\`: build first (or set GPU_CHECK_BUILD)")
  status=1
elif missing=$(ldd "$exe" 2>/dev/null | grep 'not found'); then
  notes+=("shared libraries missing for xrsc: $(echo "$missing" | awk '{print $1}' | tr '\n' ' ')")
  status=1
fi

# Runs a command in a process group of its own, killed whole after LIMIT seconds (timeout(1)
# would kill ctest and leave its test running on the GPU during the bench); 124 on a timeout.
run_limited() { # LIMIT COMMAND...
  local limit=$1 t=0
  shift
  setsid "$@" &
  local pid=$!
  while kill -0 "$pid" 2>/dev/null; do
    if ((t >= limit)); then
      kill -TERM -- "-$pid" 2>/dev/null
      sleep 2
      kill -KILL -- "-$pid" 2>/dev/null
      wait "$pid"
      return 124
    fi
    sleep 1
    t=$((t + 1))
  done
  wait "$pid"
}

# ---- the GPU tests ----
tests_md=$out/tests.md
run_tests() {
  local log=$out/ctest.log args=(-L gpu)
  [[ -n ${GPU_CHECK_TESTS:-} ]] && args=(-R "$GPU_CHECK_TESTS")
  local jobs
  jobs=$(nproc 2>/dev/null || echo 2)
  ((jobs > 8)) && jobs=8
  local t0=$SECONDS
  run_limited "$test_timeout" ctest --test-dir "$build" "${args[@]}" -j"$jobs" \
    --output-on-failure >"$log" 2>&1
  local rc=$?
  {
    echo "ctest ${args[*]} -j$jobs: exit $rc in $((SECONDS - t0)) s (limit ${test_timeout} s; \`ctest.log\` has the output)"
    echo
    echo '```'
    grep -E 'Test +#|tests passed|tests failed|Timeout' "$log"
    echo '```'
    if ((rc == 124)); then
      echo
      echo "Stopped at the limit, unfinished:" \
        "$(comm -23 <(sed -n 's/^ *Start *[0-9]*: //p' "$log" | sort) \
          <(sed -n 's/^.*Test *#[0-9]*: \([^ ]*\) .*$/\1/p' "$log" | sort) | tr '\n' ' ')"
    fi
  } >"$tests_md"
  ((rc == 0)) || status=1
}
if [[ ${GPU_CHECK_NO_TESTS:-} == 1 ]]; then
  echo "skipped (GPU_CHECK_NO_TESTS=1)" >"$tests_md"
elif [[ ! -f $build/CTestTestfile.cmake ]]; then
  echo "no CTestTestfile.cmake in \`$build\`" >"$tests_md"
  status=1
else
  echo "gpu-check: tests ..." >&2
  run_tests
fi

# ---- the benchmark at each size ----
bench_size() { # WxH
  local size=$1 dir=$out/bench-$1 t0=$SECONDS
  echo "gpu-check: bench 2x$size ..." >&2
  local scoring=(--timing-only)
  [[ ${GPU_CHECK_METRICS:-} == 1 ]] && scoring=(--score-every "$frames" --ref-spp "$ref_spp")
  (cd "$root" && timeout "$bench_timeout" "$exe" bench --device "$device" --resolution "$size" \
    --frames "$frames" --warmup "$warmup" "${scoring[@]}" --settings "$settings" --no-plots \
    --quiet --fresh --out "$dir") >"$dir.log" 2>&1
  local rc=$?
  echo
  echo "## Bench 2×$size"
  echo
  echo "\`xrsc bench --resolution $size --frames $frames --warmup $warmup ${scoring[*]} --settings '$settings'\`:" \
    "exit $rc in $((SECONDS - t0)) s (limit $bench_timeout s; folder \`bench-$size\`)"
  echo
  echo '```'
  # the summary: from the device line to the method counters
  sed -n '/^xrsc bench: .*per eye;/,$p' "$dir.log" | grep -v '^files:'
  ((rc == 0)) || tail -n 5 "$dir.log"
  echo '```'
  ((rc == 0)) || status=1
}
bench_md=$out/bench.md
: >"$bench_md"
if [[ -x $exe ]]; then
  for size in $sizes; do
    mkdir -p "$out/bench-$size"
    bench_size "$size" >>"$bench_md"
  done
fi

# ---- the report ----
{
  echo "# xrsc GPU check"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'), host: $(hostname)"
  echo "- commit: $(git -C "$root" log -1 --format='%h %s' 2>/dev/null || echo unknown)"
  echo "- device selector: \`$device\`; xrsc: $("$exe" --version 2>/dev/null | head -n1)"
  if command -v nvidia-smi >/dev/null 2>&1; then
    echo "- GPU: $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | head -n1)"
  fi
  echo "- build: \`$build\` ($(cache_value CMAKE_BUILD_TYPE))"
  if [[ ${GPU_CHECK_METRICS:-} == 1 ]]; then
    echo "- bench: sizes per eye \`$sizes\`, $frames frames per setting ($warmup warm-up), one scored frame against a ${ref_spp}-spp reference"
  else
    echo "- bench: sizes per eye \`$sizes\`, $frames frames per setting ($warmup warm-up), --timing-only (no image metrics: their columns show -)"
  fi
  for n in "${notes[@]}"; do
    echo "- note: $n"
  done
  echo
  echo "## GPU tests"
  echo
  cat "$tests_md"
  cat "$bench_md"
  echo
  echo "GPU ms: timestamp queries around each pass (per pass, mean over the frames after the"
  echo "warm-up); wall ms: CPU wall time per stereo frame."
  echo
  echo "Total: $SECONDS s; exit $status."
} >"$report"
echo "gpu-check: report in $report (exit $status)" >&2
exit "$status"
