#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file test_sweep_units.sh
# @brief `xrsc sweep` without Slurm: the plan's units, a failing unit (a scene that does not
#        exist) named by merge with its error while the other case merges, a finished unit
#        rerun as a no-op, bad units and keys (unknown, or a bench flag not forwarded) refused
#        (exit 2).
# Usage: test_sweep_units.sh XRSC SOURCE_DIR
set -uo pipefail
xrsc=$(realpath "$1"); src=$(realpath "$2")
T=$(mktemp -d /tmp/xrsc-sweep.XXXXXX); trap '[ -n "${KEEP:-}" ] || rm -rf "$T"' EXIT
cd "$T"
pass=0; fail=0
check() { if eval "$2"; then pass=$((pass+1)); else fail=$((fail+1)); echo "FAIL: $1"; fi; }
cat > s.sweep <<SWEEP
out = $T/out
scene = $src/scenes/cornell.gltf
scene = $T/no-such-scene.gltf
capture = $src/poses/orbit_cornell.xrpose, frames=6, name=orbit
setting = spp:spp=1,name=spp1
resolution = 16x16
warmup = 2
score-every = 3
ref-spp = 4
no-plots
quiet
SWEEP
"$xrsc" sweep plan s.sweep > plan.txt
check "plan: 2 cases x (2 references + 1 run)" '[ "$(grep -c "^[0-9]" plan.txt)" -eq 6 ]'
check "plan: references first, stable names" \
  'grep -q "^0 ref cornell-orbit frame=2$" plan.txt && grep -q "^5 run no-such-scene-orbit spp1$" plan.txt'
check "plan --count runs" '[ "$("$xrsc" sweep plan s.sweep --count runs)" = 2 ]'
"$xrsc" sweep run s.sweep --units all > run.out 2> run.err; rc=$?
check "run: the bad scene's units fail (exit 1)" '[ $rc -eq 1 ]'
check "run: the failure is kept" 'grep -q "no-such-scene" out/units/00005.failed'
"$xrsc" sweep merge s.sweep > merge.out 2> merge.err; rc=$?
check "merge: exit 1 with units missing" '[ $rc -eq 1 ]'
check "merge: names the failed unit and its error" \
  'grep -q "missing unit 5 (run no-such-scene-orbit spp1): failed: .*no-such-scene.gltf" merge.err'
check "merge: the complete case is merged" '[ "$(wc -l < out/cornell-orbit/bench.csv)" -eq 7 ]'
stamp() { stat -c '%n %y %s' out/cornell-orbit/frames/*.csv out/cornell-orbit/ref/*.pfm; }
before=$(stamp)
"$xrsc" sweep run s.sweep --units 0..1 2>/dev/null && "$xrsc" sweep run s.sweep --unit 4 2>/dev/null; rc=$?
check "a finished unit reruns as a no-op (exit 0, files untouched)" '[ $rc -eq 0 ] && [ "$(stamp)" = "$before" ]'
"$xrsc" sweep run s.sweep --unit 6 2> bad.err; rc=$?
check "unit out of range: exit 2" '[ $rc -eq 2 ] && grep -q "the sweep has 6 units" bad.err'
echo "colour = red" >> s.sweep
"$xrsc" sweep plan s.sweep 2> key.err; rc=$?
check "unknown key: exit 2 naming file and key" '[ $rc -eq 2 ] && grep -Eq "s.sweep:1[23]: --colour: unknown option" key.err'
grep -v '^colour' s.sweep > f.sweep && echo "fresh" >> f.sweep
"$xrsc" sweep plan f.sweep 2> flag.err; rc=$?
check "a bench flag a sweep does not forward: exit 2 naming file, line and key" \
  '[ $rc -eq 2 ] && grep -q "f.sweep:$(wc -l < f.sweep): --fresh: unknown option" flag.err'
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
