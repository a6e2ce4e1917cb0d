#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file submit.sh
# @brief Submits an `xrsc sweep` to Slurm: the references as one array job, the runs as a
#        second array job after it, the merge after the runs (README "Sweeps on a cluster").
#
# Usage: scripts/slurm/submit.sh SWEEP_FILE [sbatch options for the unit tasks...]
#   e.g. scripts/slurm/submit.sh bench/sweeps/fast_turns.sweep --gres=gpu:1 -p gpu
# Environment: XRSC (the xrsc binary the tasks run, on the shared filesystem; default the
# build's), XRSC_UNITS_PER_TASK (units per array task, default 1: keeps arrays under Slurm's
# MaxArraySize for large sweeps). Prints the three job IDs: references, runs, merge.
# The runs start when every reference task has ended (afterany: a run unit renders a reference
# a failed task left missing); the merge waits for every run task to succeed (afterok).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
sweep=${1:?usage: submit.sh SWEEP_FILE [sbatch options...]}
shift
export XRSC=${XRSC:-$here/../../build/host_sim/xrsc}
k=${XRSC_UNITS_PER_TASK:-1}
refs=$("$XRSC" sweep plan "$sweep" --count refs)
runs=$("$XRSC" sweep plan "$sweep" --count runs)
tasks() { echo $(( ($1 + k - 1) / k )); }

dep=()
jr=none
if [ "$refs" -gt 0 ]; then
  jr=$(XRSC_UNIT_BASE=0 sbatch --parsable --export=ALL,XRSC_UNIT_BASE=0 \
       --array=0-$(( $(tasks "$refs") - 1 )) "$@" "$here/sweep.sbatch" "$sweep")
  dep=(--dependency=afterany:"$jr")
fi
jn=$(sbatch --parsable --export=ALL,XRSC_UNIT_BASE="$refs" "${dep[@]}" \
     --array=0-$(( $(tasks "$runs") - 1 )) "$@" "$here/sweep.sbatch" "$sweep")
jm=$(sbatch --parsable --export=ALL --dependency=afterok:"$jn" "$here/merge.sbatch" "$sweep")
echo "$jr $jn $jm"
