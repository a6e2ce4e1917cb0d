#!/bin/bash
# SPDX-License-Identifier: MIT
# @file gpu-check.sh
# @brief Device check of the moving-sample rule (bench/results/issue19-moving2/README.md):
#        the glossy orbit and the `moving` case at 2 x 128^2, 40 frames, 128-spp references,
#        the default (with the rule since stop 22) against the default without it (bench key
#        moving=off), side by side.
#
# Usage: bench/results/issue19-moving2/gpu-check.sh XRSC OUT
#   XRSC  the built program (e.g. build/host_sim/xrsc or .dev/bin/xrsc)
#   OUT   a folder for the runs (created; each case in OUT/CASE, its summary in OUT/CASE.txt)
# Environment: VALIDATE=1 also replays `moving` with the rule for 3 frames under the
# validation layer with synchronization validation (--validation) and counts its errors.
# Prints the table lines (case, setting, relMSE, temporal, stereo, GPU ms, rays/px, ...) and
# one verdict line per case; exits 1 when a verdict fails:
# - glossy: nothing moves there, so the default must give def-nomov's figures exactly (stop 20's
#   version of the rule took glossy from 0.0036 to 0.19 on an H200);
# - moving: the default's relMSE must be below def-nomov's.
# Both cases run at once (JOBS=2); on an H100/H200 the whole check takes well under 60 s.
set -u
XRSC=$(realpath "$1")
mkdir -p "$2"
OUT=$(realpath "$2")
cd "$(dirname "$0")/../../.." || exit 2
SETTINGS=$OUT/gpu-check.settings
printf 'default:moving=off,name=def-nomov\ndefault:name=default\n' > "$SETTINGS"
start=$(date +%s)
SIZE=128 FRAMES=40 REF_SPP=128 JOBS=2 ONLY="glossy moving" \
    bench/issue19_defaults.sh "$XRSC" "$OUT" "$SETTINGS"
python3 bench/issue19_table.py "$OUT" | tee "$OUT/table.csv"
echo "bench: $(( $(date +%s) - start )) s"
fail=0
fig() { awk -F, -v c="$1" -v s="$2" '$1 == c && $2 == s {print $3}' "$OUT/table.csv"; }
g0=$(fig glossy def-nomov) g1=$(fig glossy default) m0=$(fig moving def-nomov) m1=$(fig moving default)
if [ -n "$g0" ] && [ "$g0" = "$g1" ]; then
    echo "glossy: PASS default relMSE $g1 = def-nomov $g0"
else
    echo "glossy: FAIL default relMSE '$g1' vs def-nomov '$g0' (must be equal)"; fail=1
fi
if [ -n "$m0" ] && [ -n "$m1" ] && python3 -c "import sys; sys.exit(0 if $m1 < $m0 else 1)"; then
    echo "moving: PASS default relMSE $m1 < def-nomov $m0"
else
    echo "moving: FAIL default relMSE '$m1' vs def-nomov '$m0' (must be lower)"; fail=1
fi
if [ "${VALIDATE:-0}" = 1 ]; then
    "$XRSC" replay --direct --validation --frames 3 --resolution 64x64 --write none \
        --scene scenes/moving.gltf --poses poses/still.xrpose --sc-moving on --overwrite \
        --out "$OUT/validate" > "$OUT/validate.log" 2>&1
    rc=$?
    n=$(grep -c -E 'SYNC-HAZARD|Validation Error' "$OUT/validate.log")
    echo "validation (moving, --sc-moving on, 3 frames 64^2): rc $rc, $n errors/hazards"
    [ "$rc" = 0 ] && [ "$n" = 0 ] || fail=1
fi
echo "total: $(( $(date +%s) - start )) s"
exit $fail
