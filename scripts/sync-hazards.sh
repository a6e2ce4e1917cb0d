#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file sync-hazards.sh
# @brief Replays every method, sample-cache option, post-pass and both paths (direct, OpenXR)
#        under the Vulkan validation layer with synchronization validation on, and fails on any
#        SYNC-HAZARD (or other validation error) line.
#
# Usage: scripts/sync-hazards.sh [XRSC_EXE [OUT_DIR]]
#   XRSC_EXE  the built program (default build/host_sim/xrsc)
#   OUT_DIR   scratch folder for the runs and their logs (default out/sync-hazards; wiped)
# Environment: SYNC_SIZE (per-eye WxH, default 32x32), SYNC_FRAMES (default 3), SYNC_ONLY (a
# regular expression: run only the configurations whose name matches), SYNC_SKIP (a regular
# expression: skip those whose name matches; applied after SYNC_ONLY).
# lavapipe runs commands one after another, so a missing barrier never changes an image here;
# synchronization validation finds it anyway (issue 20). Prints one line per configuration and
# `N passed, N failed`; exits 1 when any configuration has a hazard or fails.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
exe=${1:-$root/build/host_sim/xrsc}
out=${2:-$root/out/sync-hazards}
size=${SYNC_SIZE:-32x32}
frames=${SYNC_FRAMES:-3}
only=${SYNC_ONLY:-}
skip=${SYNC_SKIP:-}

# name | arguments (word-split; a later --write overrides --write none); names ending in _xr
# run through OpenXR, the rest --direct
configs=(
  "spp|--method spp --spp 1"
  "primary|--method primary"
  "samplecache|--method samplecache"
  "sc_trace_single|--method samplecache --sc-trace single"
  "sc_trace_multi|--method samplecache --sc-trace multi"
  "sc_reproject_2pass|--method samplecache --sc-reproject 2pass"
  "sc_shading_cache_off|--method samplecache --sc-shading-cache off"
  "sc_shade_uniform|--method samplecache --sc-shade uniform"
  "sc_shade_adaptive|--method samplecache --sc-shade adaptive --sc-shade-rate 50"
  "sc_shade_adaptive_variance|--method samplecache --sc-shade adaptive-variance"
  "sc_alpha_fixed|--method samplecache --sc-alpha fixed --sc-alpha-fixed 0.2"
  "sc_cross_eye|--method samplecache --sc-cross-eye on"
  "sc_stratify|--method samplecache --sc-stratify on"
  "sc_visibility_cache|--method samplecache --sc-visibility-cache on"
  "sc_visibility_strict|--method samplecache --sc-visibility-cache on --sc-visibility-refine strict"
  "sc_visibility_none|--method samplecache --sc-visibility-cache on --sc-visibility-refine none"
  "sc_numbers|--method samplecache --sc-slots 4 --sc-target 2 --sc-delta 0.5 --sc-eps0 0.01 --sc-eps1 0.01 --sc-block 2"
  "sc_moving|--method samplecache --sc-moving on --scene $root/scenes/moving.gltf --poses $root/poses/still.xrpose"
  "taa|--method taa"
  "hashcache|--method hashcache --hc-table 4096"
  "hashcache_normal_lod|--method hashcache --hc-table 4096 --hc-lod distance-normal --hc-voxel-jitter off"
  "hybrid|--method hybrid --hc-table 4096"
  "isrt|--method isrt"
  "isrt_m1_single|--method isrt --isrt-m 1 --sc-trace single"
  "blend_pfj23|--method samplecache --blend pfj23"
  "blend_moments_r|--method samplecache --blend moments --blend-r 0.5 --blend-estimate mean"
  "spp_blend_pfj23|--method spp --spp 1 --blend pfj23"
  "spp_taa_on|--method spp --spp 1 --taa on"
  "sc_taa_pfj23|--method samplecache --taa pfj23"
  "taa_blend_moments|--method taa --blend moments"
  "hybrid_no_post|--method hybrid --hc-table 4096 --taa off --blend none"
  "isrt_shade_variance|--method isrt --sc-shade adaptive-variance --sc-visibility-cache on"
  "spp_4_no_bounce|--method spp --spp 4 --bounces 0"
  "taa_pfj23|--method taa --taa pfj23"
  "sc_read_back|--method samplecache --write eyes,linear,exr"
  "hashcache_read_back|--method hashcache --hc-table 4096 --write eyes,exr"
  "default_xr|"
  "spp_xr|--method spp --spp 1"
  "hashcache_xr|--method hashcache --hc-table 4096"
  "isrt_taa_xr|--method isrt --taa on --blend pfj23"
  "taa_read_back_xr|--method taa --write eyes,linear"
)

if [[ ! -x $exe ]]; then
  echo "sync-hazards: no program at $exe (build first)" >&2
  exit 2
fi
rm -rf "$out"
mkdir -p "$out"
# No VK_LAYER_ENABLES: --validation itself turns synchronization validation on (gpu_context.c).
passed=0
failed=0
total_hazards=0
printf '%-28s %8s %8s %5s\n' configuration hazards errors exit
for entry in "${configs[@]}"; do
  name=${entry%%|*}
  args=${entry#*|}
  if [[ -n $only && ! $name =~ $only ]] || [[ -n $skip && $name =~ $skip ]]; then
    continue
  fi
  path=(--direct)
  [[ $name == *_xr ]] && path=()
  log=$out/$name.log
  # shellcheck disable=SC2086 # the arguments are word lists on purpose
  "$exe" replay "${path[@]}" --validation --frames "$frames" --resolution "$size" \
    --write none --out "$out/$name" $args >"$log" 2>&1
  rc=$?
  hazards=$(grep -c 'SYNC-HAZARD' "$log")
  errors=$(grep -c 'Validation Error' "$log")
  total_hazards=$((total_hazards + hazards))
  printf '%-28s %8d %8d %5d\n' "$name" "$hazards" "$errors" "$rc"
  if ((hazards == 0 && errors == 0 && rc == 0)); then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    grep -m3 -E 'SYNC-HAZARD|Validation Error|error' "$log" | cut -c1-400 | sed 's/^/    /'
  fi
done
echo "SYNC-HAZARD lines in all: $total_hazards"
echo "$passed passed, $failed failed"
((failed == 0))
