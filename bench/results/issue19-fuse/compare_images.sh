#!/bin/sh
# SPDX-License-Identifier: MIT
# @file compare_images.sh
# @brief Renders the same replays with two builds of xrsc (BEFORE, AFTER) and compares every
#        linear frame (PFM, both eyes) byte for byte: the fused passes must not change images.
# usage: compare_images.sh BEFORE_XRSC AFTER_XRSC OUTDIR
set -u
before=$1 after=$2 out=$3
frames=12
same=0 differ=0
run_case() { # name, options...
    name=$1; shift
    for b in before after; do
        exe=$before; [ $b = after ] && exe=$after
        rm -rf "$out/$name/$b"; mkdir -p "$out/$name"
        nice "$exe" replay --direct --frames $frames --resolution 64x64 --write linear \
            --out "$out/$name/$b" "$@" >"$out/$name/$b.log" 2>&1 || echo "$name $b: failed"
    done
    n=0 d=0
    for f in "$out/$name/before"/*.pfm; do
        n=$((n + 1))
        cmp -s "$f" "$out/$name/after/$(basename "$f")" || d=$((d + 1))
    done
    echo "$name: $((n - d)) of $n frames identical"
    if [ $d -gt 0 ]; then # is BEFORE itself reproducible? (hybrid's hash table is not)
        nice "$before" replay --direct --frames $frames --resolution 64x64 --write linear \
            --out "$out/$name/before2" "$@" >/dev/null 2>&1
        r=0
        for f in "$out/$name/before"/*.pfm; do
            cmp -s "$f" "$out/$name/before2/$(basename "$f")" || r=$((r + 1))
        done
        echo "  (BEFORE run twice: $((n - r)) of $n frames identical)"
    fi
    [ $d -eq 0 ] && [ $n -gt 0 ] && same=$((same + 1)) || differ=$((differ + 1))
}
mkdir -p "$out"
run_case default
run_case default-1bounce --bounces 1
run_case no-taa-no-blend --taa off --blend none
run_case pfj23 --taa off --blend pfj23
run_case trace-single --sc-trace single --taa off
run_case trace-multi --sc-trace multi --taa off
run_case reproject-2pass --sc-reproject 2pass
run_case cross-eye --sc-cross-eye on --sc-shade adaptive-variance
run_case shade-uniform --sc-shade uniform --taa off
run_case shade-adaptive --sc-shade adaptive
run_case no-shading-cache --sc-shading-cache off
run_case visibility-cache --sc-visibility-cache on
run_case isrt --method isrt
run_case hybrid --method hybrid
run_case odd-size --resolution 45x37 --bounces 1
candle=${XRSC_SHARED_DIR:-/work/shared}/scenes/GlassHurricaneCandleHolder
run_case candle --scene "$candle/GlassHurricaneCandleHolder.gltf" --frame
echo "$same cases identical, $differ differ"
