#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file test_host_layers.sh
# @brief Issue 22 item 1: no host_sim library includes a header of a library above it
#        (scripts/check-host-layers.sh passes on the tree), and the check would catch one that
#        did (it fails on a copy of host_sim/ given an upward include: io including a bench
#        header, and the runtime including a replay header).
# Usage: test_host_layers.sh SOURCE_DIR
set -u
src=$1
check=$src/scripts/check-host-layers.sh
passed=0 failed=0
expect() { # expect NAME WANT_STATUS DIR
  "$check" "$3" > "$tmp/out.txt" 2>&1
  local rc=$?
  if { [ "$2" = 0 ] && [ $rc = 0 ]; } || { [ "$2" != 0 ] && [ $rc != 0 ]; }; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1)); echo "FAIL: $1 (status $rc)"; cat "$tmp/out.txt"
  fi
}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

expect "the tree keeps its layers" 0 "$src/host_sim"

cp -r "$src/host_sim" "$tmp/up1"
printf '#include "hs_bench.h"\n' >> "$tmp/up1/io/hs_file.c"
expect "io including bench is caught" 1 "$tmp/up1"
grep -q 'io/hs_file.c:.*hs_bench.h' "$tmp/out.txt" && passed=$((passed + 1)) ||
  { failed=$((failed + 1)); echo "FAIL: the violation is not named"; cat "$tmp/out.txt"; }

cp -r "$src/host_sim" "$tmp/up2"
printf '#include "hs_replay.h"\n' >> "$tmp/up2/runtime/hsrt_handle.c"
expect "runtime including replay is caught" 1 "$tmp/up2"

echo "$passed passed, $failed failed"
[ $failed = 0 ]
