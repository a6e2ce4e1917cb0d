#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file run_conformance.sh
# @brief ctest `test_xr_conformance` (label conformance): the Khronos OpenXR CTS's
#        non-interactive suite against this build's runtime; fails on any failed test case,
#        on a crash, and when no test case ran.
#
# usage: run_conformance.sh <CTS folder> <runtime manifest>
# Exits 77 (ctest SKIP_RETURN_CODE) when the CTS folder is missing (it is prebuilt in
# ../shared/tools/openxr-cts, not part of the repository).
#
# Timed_Pipelined_Frame_Submission compares frame submission with and without a pipelined
# frame against a 50 % limit. At the simulated headset's full eye size (2064x2208) the frame
# time is lavapipe's CPU rendering of the CTS's scene, which varies with the machine's load by
# more than that, so that test case alone runs at XRSC_RT_EYE_SIZE=CONF_TIMED_EYE_SIZE, where it
# measures the runtime's frame loop rather than CPU rendering speed.
set -u
cts_dir=$1
manifest=$2
CONF_TIMED_EYE_SIZE=256x256
CONF_TIMED_TEST=Timed_Pipelined_Frame_Submission

if [ ! -x "$cts_dir/run-cts.sh" ]; then
    echo "SKIP: no OpenXR CTS at $cts_dir (run-cts.sh missing): conformance not tested"
    echo "0 passed, 0 failed"
    exit 77
fi
export XR_RUNTIME_JSON=$manifest
log_dir=$(mktemp -d)
trap 'rm -rf "$log_dir"' EXIT
passed=0
failed=0

# One run of the CTS: label, then its arguments. Counts the test cases; a crash, a non-zero
# exit or a failed test case counts as a failure.
run_cts() {
    local label=$1 log="$log_dir/$1.log"
    shift
    local start=$SECONDS
    "$cts_dir/run-cts.sh" "$@" --reporter console >"$log" 2>&1
    local rc=$?
    # Catch2's summary: "test cases: N | P passed | F failed | S skipped" (or "All tests passed").
    local summary
    summary=$(grep -E "^test cases:|^All tests passed" "$log" | tail -n 1)
    echo "$label: exit $rc in $((SECONDS - start)) s: ${summary:-no summary (crash?)}"
    if [ "$rc" -ne 0 ] || [ -z "$summary" ] || ! grep -qE "[1-9][0-9]* (passed|test case)" <<<"$summary"; then
        echo "---- $label: the end of the CTS's output ----"
        tail -n 80 "$log"
        grep -E "FAILED|^[^ ].*\.cpp:[0-9]+: FAILED" -A 6 "$log" | head -n 120
        failed=$((failed + 1))
    else
        passed=$((passed + 1))
    fi
}

run_cts suite "exclude:[interactive] exclude:$CONF_TIMED_TEST" -G vulkan2 --apiVersion 1.0
XRSC_RT_EYE_SIZE=$CONF_TIMED_EYE_SIZE run_cts timed "$CONF_TIMED_TEST" -G vulkan2 --apiVersion 1.0
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
