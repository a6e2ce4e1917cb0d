#!/bin/bash
# SPDX-License-Identifier: MIT
# Issue 19 item 1: bench/issue19_defaults.settings over the bundled cases, one `xrsc bench`
# run per case at 2 x SIZE^2 (or 2 x WxH where SIZE=WxH), FRAMES frames (warm-up 8, scored every 4, REF_SPP-spp
# references), JOBS cases at a time (ONLY="a b": those cases alone; EXTRA: more bench options,
# e.g. EXTRA=--timing-only JOBS=1 for the GPU times of each case alone). Usage: bench/issue19_defaults.sh XRSC OUT [SETTINGS]; the table:
# python3 bench/issue19_table.py OUT > table.csv (bench/results/issue19-defaults/).
set -e
XRSC=$1
OUT=$2
SETTINGS=${3:-bench/issue19_defaults.settings}
SIZE=${SIZE:-48}
RES=$SIZE; [[ $RES == *x* ]] || RES=${SIZE}x${SIZE}
FRAMES=${FRAMES:-24}
REF_SPP=${REF_SPP:-64}
JOBS=${JOBS:-2}
mkdir -p "$OUT"
HOLO=../shared/poses/pred6dof-hololens/1.csv
# name scene poses start_s: the Cornell and glossy orbits, the candle holder on the same
# orbit, the HoloLens capture's fastest second (xrsc poses stats --fastest 1), and the
# stability suite's cases (hs_bench_suite.c) started so that each event falls after the
# warm-up (headturn-hololens is the fastest second's case)
one() { # name scene poses start
    "$XRSC" bench --scene "$2" --poses "$3" --start "$4" \
        --resolution "$RES" --frames "$FRAMES" --warmup 8 --score-every 4 \
        --ref-spp "$REF_SPP" --settings "@$SETTINGS" --baseline default --no-plots --quiet $EXTRA \
        --out "$OUT/$1" > "$OUT/$1.txt" 2>&1 || echo "$1: failed" >&2
}
cases() {
    cat <<CASES
cornell scenes/cornell.gltf poses/orbit_cornell.xrpose 0
glossy scenes/glossy.gltf poses/orbit_cornell.xrpose 0
candle ../shared/scenes/GlassHurricaneCandleHolder/GlassHurricaneCandleHolder.gltf poses/orbit_cornell.xrpose 0
hololens scenes/headturn.gltf $HOLO 43.494942
strands scenes/strands.gltf poses/strands.xrpose 0
headturn scenes/headturn.gltf poses/headturn.xrpose 0.866667
edges scenes/edges.gltf poses/pan.xrpose 0.066667
specular scenes/specular.gltf poses/orbit_specular.xrpose 0
moving scenes/moving.gltf poses/still.xrpose 0
disocclusion scenes/disocclusion.gltf poses/sideways.xrpose 0
CASES
}
while read -r name scene poses start; do
    [ -z "$name" ] && continue
    [ -n "$ONLY" ] && [[ " $ONLY " != *" $name "* ]] && continue
    one "$name" "$scene" "$poses" "$start" &
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
done < <(cases)
wait
