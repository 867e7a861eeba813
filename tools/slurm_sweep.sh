#!/usr/bin/env bash
# The example sweep under a real Slurm scheduler, on this machine: a single-node cluster
# (munged, slurmctld, slurmd from Debian's slurm-wlm, started here and stopped on exit), the
# example script examples/sweep-slurm.sh submitted as an array job (`sbatch --array=1-4
# --wait`), its shards merged, and the merged summary compared with the same sweep run in one
# process. Fails (non-zero exit, the daemons' logs printed) when the daemons do not come up
# within $SLURM_UP_SECONDS (default 90), when the job does not end within
# $SLURM_JOB_SECONDS (default 600), or when the summaries differ.
#
#   tools/slurm_sweep.sh [LINKAGE_BINARY]     # default target/release/linkage; run as root
#
# Everything is written under target/slurm (its own slurm.conf through SLURM_CONF, state
# and spool folders, logs): nothing in /etc/slurm is touched.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
bin=$(realpath "${1:-target/release/linkage}")
[ -x "$bin" ] || { echo "slurm_sweep: no linkage binary at $bin" >&2; exit 2; }
up_seconds=${SLURM_UP_SECONDS:-90}
job_seconds=${SLURM_JOB_SECONDS:-600}

if ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null
fi

work=$root/target/slurm
rm -rf "$work"
mkdir -p "$work"/{state,spool,run}
host=$(hostname -s)
cpus=$(nproc)
export SLURM_CONF=$work/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=linkage-ci
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/run/slurmctld.pid
SlurmdPidFile=$work/run/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
EOF

pids=()
munge_started=0
cleanup() {
    set +e
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
    for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
    if [ "$munge_started" = 1 ]; then munged --stop >/dev/null 2>&1; fi
}
trap cleanup EXIT
fail() {
    echo "slurm_sweep: $*" >&2
    for log in "$work"/slurmctld.log "$work"/slurmd.log; do
        [ -f "$log" ] && { echo "--- $log (last lines)" >&2; tail -n 20 "$log" >&2; }
    done
    exit 1
}

# munge: the credentials both daemons and the clients check.
if ! munge -n </dev/null >/dev/null 2>&1; then
    [ -s /etc/munge/munge.key ] || { mungekey --create 2>/dev/null || create-munge-key -f; }
    mkdir -p /run/munge && chown munge:munge /run/munge
    runuser -u munge -- munged || fail "munged did not start"
    munge_started=1
fi
munge -n </dev/null | unmunge >/dev/null || fail "munge credentials do not verify"

slurmctld -D -c -f "$SLURM_CONF" >"$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/slurmd.out" 2>&1 &
pids+=($!)
deadline=$((SECONDS + up_seconds))
until sinfo -h -N -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; do
    for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null || fail "a Slurm daemon exited"; done
    [ $SECONDS -lt $deadline ] || fail "the node was not idle within ${up_seconds} s: $(sinfo -N 2>&1 | tail -n 1)"
    sleep 1
done
echo "slurm_sweep: single-node cluster up: $(sinfo -h -N -o '%N %T %c CPUs')"

# The example array job, as a user would submit it (its #SBATCH lines give --array=1-4),
# with the logs and the sweep folder under target/slurm; the binary's folder on PATH (sbatch
# exports the submitting environment).
out=$work/sweep-out
export PATH="$(dirname "$bin"):$PATH" LINKAGE_SWEEP_OUT=$out
timeout "$job_seconds" sbatch --wait --chdir="$root" --output="$work/sweep-%A_%a.log" \
    examples/sweep-slurm.sh || {
    squeue 2>&1 | tail -n 5 >&2
    cat "$work"/sweep-*.log >&2 2>/dev/null || true
    fail "the array job failed or did not end within ${job_seconds} s"
}
tasks=$(ls -d "$out"/shard-*-of-4 2>/dev/null | wc -l)
[ "$tasks" = 4 ] || fail "expected 4 shard folders from the 4 array tasks, found $tasks"
"$bin" sweep merge "$out" >/dev/null

# The same sweep in one process (no Slurm variables), merged, compared.
single=$work/single-out
env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_MIN -u SLURM_ARRAY_TASK_COUNT \
    "$bin" sweep examples/spring_mass_sweep.toml --out "$single" >/dev/null
"$bin" sweep merge "$single" >/dev/null
runs=$(($(wc -l <"$single/summary.csv") - 1))
if ! diff -u "$single/summary.csv" "$out/summary.csv"; then
    fail "the array job's summary differs from the one-process sweep"
fi
echo "slurm_sweep: ok: $runs runs in 4 array tasks under Slurm, summary identical to the one-process sweep"
