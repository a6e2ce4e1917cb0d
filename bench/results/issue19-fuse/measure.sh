#!/bin/sh
# SPDX-License-Identifier: MIT
# @file measure.sh
# @brief Alternating lavapipe runs of two builds (before, after, before, ...), fuse.settings
#        (or SETTINGS, e.g. ../issue19-shadeperf/shadeperf.settings) at 2 x 256^2, 1 bounce, under chrt -f 10 as issue19-speed3 measured; per run the bench's
#        summary with the load average appended, and its bench.csv (every frame's pass times).
# usage: [SETTINGS=FILE] measure.sh BEFORE_XRSC AFTER_XRSC RUNS RESULT_DIR [TAG]
set -u
before=$1 after=$2 runs=$3 dir=$4 tag=${5:-lavapipe}
here=$(dirname "$0")
settings=${SETTINGS:-$here/fuse.settings}
work=/tmp/$(basename "$settings" .settings)-bench
uptime >"$dir/$tag-uptime-start.txt"
i=1
while [ $i -le "$runs" ]; do
    for v in before after; do
        exe=$before; [ $v = after ] && exe=$after
        f="$dir/$tag-$v-$i.txt"
        chrt -f 10 "$exe" bench --resolution 256x256 --frames 24 --warmup 4 --timing-only \
            --settings "@$settings" --baseline spp1 --no-plots --quiet --fresh \
            --out "$work/$tag-$v-$i" >"$f" 2>&1
        uptime >>"$f"
        cp "$work/$tag-$v-$i/bench.csv" "$dir/$tag-$v-$i.csv" # per-frame pass times
    done
    i=$((i + 1))
done
uptime >"$dir/$tag-uptime-end.txt"
