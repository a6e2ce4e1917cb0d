#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file test_sweep_slurm.sh
# @brief A real one-node Slurm (munged, slurmctld, slurmd started here as local processes)
#        runs a small `xrsc sweep` through scripts/slurm/submit.sh; the merged CSVs must equal
#        single-process `xrsc bench` runs in every column but the timing ones. Then one task is
#        killed mid-run: merge names the missing unit, nothing else is lost, and a resubmitted
#        task brings the same result back. Exit 77 (skipped) without slurmctld/slurmd/munged.
# Usage: test_sweep_slurm.sh XRSC SOURCE_DIR
set -uo pipefail
xrsc=$(realpath "$1"); src=$(realpath "$2")
for d in slurmctld slurmd munged sbatch; do
  command -v "$d" >/dev/null || [ -x "/usr/sbin/$d" ] || { echo "skipped: no $d"; exit 77; }
done
export PATH=$PATH:/usr/sbin
T=$(mktemp -d /tmp/xrsc-slurm.XXXXXX)
pass=0; fail=0
check() { if eval "$2"; then pass=$((pass+1)); else fail=$((fail+1)); echo "FAIL: $1"; fi; }

stop_daemons() {
  for p in slurmd slurmctld; do [ -f "$T/$p.pid" ] && kill "$(cat "$T/$p.pid")" 2>/dev/null; done
  [ -f "$T/munged.pid" ] && kill "$(cat "$T/munged.pid")" 2>/dev/null
  sleep 1; rm -rf "$T"
}
trap stop_daemons EXIT

# ---- one node: munge, controller, node daemon, ports of this process's own ----
mkdir -p "$T/state" "$T/spool" "$T/log" && chmod 700 "$T"
head -c 1024 /dev/urandom > "$T/munge.key" && chmod 600 "$T/munge.key"
munged -S "$T/munge.sock" --key-file="$T/munge.key" --log-file="$T/log/munged.log" \
  --pid-file="$T/munged.pid" --seed-file="$T/munged.seed" -f || { echo "munged failed"; exit 1; }
port=$((20000 + $$ % 20000)); host=$(hostname -s)
cat > "$T/slurm.conf" <<CONF
ClusterName=xrsctest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=$(id -un)
AuthType=auth/munge
AuthInfo=socket=$T/munge.sock
CredType=cred/munge
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=xrsc Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$T/slurm.conf
slurmctld -i && slurmd || { echo "slurm daemons failed"; tail "$T"/log/*.log; exit 1; }
for _ in $(seq 120); do sinfo -h -o %T 2>/dev/null | grep -q idle && break; sleep 0.5; done
check "the node is idle" 'sinfo -h -o %T | grep -q idle'

# ---- the sweep: 2 settings x 2 captures x 3 scored frames at 32x32 ----
cat > "$T/s.sweep" <<SWEEP
out = $T/out
scene = $src/scenes/cornell.gltf
capture = $src/poses/orbit_cornell.xrpose, frames=9, name=orbit
capture = $src/poses/orbit_cornell.xrpose, start=1, frames=9, name=later
setting = spp:spp=1,name=spp1
setting = samplecache:bounces=1,name=sc
resolution = 32x32
warmup = 2
score-every = 3
ref-spp = 16
no-plots
quiet
SWEEP
cd "$T"
wait_jobs() { for _ in $(seq 1200); do [ -z "$(squeue -h)" ] && return 0; sleep 0.5; done; return 1; }
ids=$(XRSC=$xrsc "$src/scripts/slurm/submit.sh" "$T/s.sweep") || { echo "submit failed"; exit 1; }
echo "jobs (refs runs merge): $ids"
check "the sweep's jobs end" wait_jobs
check "6 reference and 4 run units planned" \
  '[ "$("$xrsc" sweep plan s.sweep --count refs) $("$xrsc" sweep plan s.sweep --count runs)" = "6 4" ]'
check "the merge job merged every case" 'grep -q "merged 2 of 2 cases; 0 units missing" slurm-xrsc-sweep-merge-*.out'

# The single process: xrsc bench of each case with the same options.
bench() { # NAME START
  "$xrsc" bench --scene "$src/scenes/cornell.gltf" --poses "$src/poses/orbit_cornell.xrpose" \
    --start "$2" --frames 9 --settings "spp:spp=1,name=spp1;samplecache:bounces=1,name=sc" \
    --resolution 32x32 --warmup 2 --score-every 3 --ref-spp 16 --no-plots --quiet \
    --out "$T/single/$1" >/dev/null
}
bench orbit 0 && bench later 1
# Every column but the timing ones (wall_ms, gpu_ms, gpu_<pass>_ms).
quality() { awk -F, 'NR==1{for(i=1;i<=NF;i++) keep[i]=($i!="wall_ms" && $i!~/^gpu_/)}
  {s=""; for(i=1;i<=NF;i++) if(keep[i]) s=s $i ","; print s}' "$1"; }
same() { [ "$(wc -l < "$T/out/cornell-$1/bench.csv")" -eq 19 ] &&
         cmp -s <(quality "$T/out/cornell-$1/bench.csv") <(quality "$T/single/$1/bench.csv"); }
for c in orbit later; do
  check "merged $c = single-process bench (18 rows, every quality column)" "same $c"
done

# ---- a task killed mid-run: unit 9 (run cornell-later sc) ----
others() { (cd "$T/out" && find . -path ./units -prune -o -type f \( -name '*.pfm' -o -path '*/frames/*' \) \
            ! -path ./cornell-later/frames/sc.csv ! -name '*.part.*' -print | sort | xargs md5sum); }
before=$(others)
killed=0
for attempt in 1 2 3; do
  rm -f "$T/out/cornell-later/frames/sc.csv"
  jk=$(sbatch --parsable --array=9 --export=ALL,XRSC="$xrsc" "$src/scripts/slurm/sweep.sbatch" s.sweep)
  for _ in $(seq 2400); do ls "$T"/out/cornell-later/frames/sc.csv.part.* >/dev/null 2>&1 && break; sleep 0.05; done
  pid=$(pgrep -f "sweep run s.sweep --units 9..9" | head -1)
  [ -n "$pid" ] && kill -STOP "$pid"   # held mid-run while Slurm cancels the task
  scancel "$jk"; [ -n "$pid" ] && kill -CONT "$pid" 2>/dev/null
  wait_jobs
  if [ ! -f "$T/out/cornell-later/frames/sc.csv" ]; then killed=1; break; fi
  echo "attempt $attempt: the task finished before it was killed; again"
done
check "the task was killed before its CSV was complete" '[ $killed -eq 1 ]'
"$xrsc" sweep merge s.sweep > merge2.out 2> merge2.err; rc=$?
check "merge after the kill fails (exit 1)" '[ $rc -eq 1 ]'
check "merge names the missing unit" 'grep -q "missing unit 9 (run cornell-later sc)" merge2.err'
check "the other case still merges" 'grep -q "merged 1 of 2 cases; 1 units missing" merge2.err'
check "no other unit's file was lost or changed" '[ "$(others)" = "$before" ]'
jr=$(sbatch --parsable --array=9 --export=ALL,XRSC="$xrsc" "$src/scripts/slurm/sweep.sbatch" s.sweep)
wait_jobs
"$xrsc" sweep merge s.sweep > merge3.out 2> merge3.err; rc=$?
check "merge after the resubmitted unit succeeds" '[ $rc -eq 0 ]'
for c in orbit later; do
  check "merged $c = single-process bench again" "same $c"
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
