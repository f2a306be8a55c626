#!/bin/bash
# A real Slurm test (issues 12, 29): installs Debian's slurm-wlm and munge, starts a one-node
# cluster (munged, slurmctld, slurmd, a minimal slurm.conf written here), submits a small map
# as an array job of 3 shards with the merge as a dependent job (scripts/slurm/submit.sh),
# waits, and compares map.csv and the pictures with a one-machine run value for value; then
# the same for a continuation in 4 segments as 2 shards (`rubsim continue --segments`).
# Skips (exit 0, with a message) when not root. Stops only the daemons it started.
#
#   bash scripts/slurm/ci_test.sh [path/to/rubsim]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(readlink -f "${1:-$repo/target/release/rubsim}")
if [ "$(id -u)" != 0 ]; then
    echo "slurm test skipped: needs root (installs slurm-wlm and munge, starts daemons)"
    exit 0
fi
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge >/dev/null
fi
work=$(mktemp -d /tmp/rubsim-slurm.XXXXXX)
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    for p in "${pids[@]}"; do
        for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    done
    rm -rf "$work"
}
trap cleanup EXIT
host=$(hostname -s)
mkdir -p "$work"/{state,spool,munge,run}
# munge: a key of our own and a daemon on our own socket.
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
sock="$work/munge/munge.socket"
munged --force --key-file="$work/munge/munge.key" --socket="$sock" \
    --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
    --seed-file="$work/munge/seed"
pids+=("$(cat "$work/munge/munged.pid")")
cat > "$work/slurm.conf" <<CONF
ClusterName=rubsimci
SlurmctldHost=$host
SlurmUser=root
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/run/slurmctld.pid
SlurmdPidFile=$work/run/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -f "$SLURM_CONF"
for _ in $(seq 50); do [ -s "$work/run/slurmctld.pid" ] && break; sleep 0.2; done
pids+=("$(cat "$work/run/slurmctld.pid")")
slurmd -f "$SLURM_CONF"
for _ in $(seq 50); do [ -s "$work/run/slurmd.pid" ] && break; sleep 0.2; done
pids+=("$(cat "$work/run/slurmd.pid")")
for _ in $(seq 100); do
    sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed)' && break
    sleep 0.3
done
sinfo -h -o '%P %T %D' | grep -qE 'idle|mixed' || {
    echo "slurm test: the node did not come up"; tail -20 "$work"/slurm*.log; exit 1
}
# A 6 × 2 map of the paper case, short runs, as 3 shards (at most 2 running).
sets=(--set 'run.map.x={ key = "speed_ratio", values = [0.8, 1.7, 2.5, 3.1, 4.2, 4.9] }'
      --set 'run.map.y={ key = "stator.0.clearance_nd", values = [0.4, 0.8] }'
      --set run.revolutions=120 --set run.transient_revolutions=60)
scene=$repo/scenes/paper/regime_map.toml
"$bin" map "$scene" "${sets[@]}" --out "$work/one" --jobs 1 >/dev/null
cd "$work"
# Waits for every job to leave the queue (3 minutes at most).
wait_jobs() {
    for _ in $(seq 600); do
        [ -z "$(squeue -h -o %i)" ] && break
        sleep 0.3
    done
    if [ -n "$(squeue -h -o %i)" ]; then
        echo "slurm test: jobs still queued after 3 minutes"; squeue; exit 1
    fi
}
RUBSIM=$bin "$repo/scripts/slurm/submit.sh" map "$scene" "$work/dist" 3 2 "${sets[@]}"
wait_jobs
cat "$work"/rubsim-merge-*.out
strip() { cut -d, -f1-17 "$1"; } # map.csv without its last column (wall_s)
if ! diff <(strip "$work/one/map.csv") <(strip "$work/dist/map.csv"); then
    echo "slurm test: the merged map.csv differs from the one-machine run"; exit 1
fi
for f in regime_map.png orbit_size_map.png contact_force_map.png; do
    cmp "$work/one/$f" "$work/dist/$f"
done
ls -d "$work"/dist/shard-*-of-3 | wc -l | grep -qx 3
echo "slurm test: 3 shards on a one-node Slurm merged into the one-machine map, value for value"
# A continuation of the paper case in 4 segments as an array of 2 shards (issue 29): the merged
# branch equals the one-machine run's, byte for byte.
paper=$repo/scenes/paper/partial_rub.toml
csets=(--set run.revolutions=120 --set run.transient_revolutions=60
       --from 1.6 --to 2.6 --step 0.1 --period 1 --segments 4)
"$bin" continue "$paper" "${csets[@]}" --out "$work/cone" >/dev/null
RUBSIM=$bin "$repo/scripts/slurm/submit.sh" continue "$paper" "$work/cdist" 2 2 "${csets[@]}"
wait_jobs
cat "$work"/rubsim-merge-*.out | tail -3
for f in branch.csv bifurcations.csv; do
    cmp "$work/cone/$f" "$work/cdist/$f" || { echo "slurm test: the merged $f differs"; exit 1; }
done
ls -d "$work"/cdist/shard-*-of-2 | wc -l | grep -qx 2
echo "slurm test: a continuation in 4 segments on 2 Slurm shards merged into the one-machine branch"
