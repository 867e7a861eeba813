#!/bin/bash
# A linkage sweep as a Slurm array job: each array task runs one shard of the sweep, all
# writing under the same shared folder; a last job, started when every task has ended,
# merges them.
#
#   jid=$(sbatch --parsable examples/sweep-slurm.sh)
#   sbatch --dependency=afterany:$jid --wrap "linkage sweep merge sweep-out"
#
# `linkage sweep` reads its shard from SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_MIN and
# SLURM_ARRAY_TASK_COUNT (here task 1..4 runs the run indices i with i mod 4 = task - 1), so
# the same command works with any contiguous --array range. A task that fails can be
# resubmitted alone (sbatch --array=3 ...): it rewrites its shard's records, and the merge
# refuses to write summary.csv while any run has no record. LINKAGE_SWEEP_OUT names the
# shared folder (default sweep-out); tools/slurm_sweep.sh submits this script in CI.
#SBATCH --job-name=linkage-sweep
#SBATCH --array=1-4
#SBATCH --cpus-per-task=2
#SBATCH --time=00:30:00
#SBATCH --output=sweep-%A_%a.log
set -euo pipefail
linkage sweep examples/spring_mass_sweep.toml --out "${LINKAGE_SWEEP_OUT:-sweep-out}" \
    --jobs "${SLURM_CPUS_PER_TASK:-1}"
