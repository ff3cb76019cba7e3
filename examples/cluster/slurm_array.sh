#!/usr/bin/env bash
# Converting a motion library on a Slurm cluster: one array task per shard, then one merge.
#
#   jobid=$(sbatch --parsable --array=1-8 examples/cluster/slurm_array.sh /data/mocap /shared/out/g1)
#   sbatch --dependency=afterany:$jobid --wrap "retarget merge-summaries /shared/out/g1 /shared/out/g1"
#
# Every task runs `retarget batch --shard I/N` on the same input: shard I gets a deterministic,
# size-balanced 1/N of the clips (the same split on every node), and all shards write into one
# output folder on a shared filesystem (each shard holds its own lock and writes
# summary-shard-I-of-N.json/.csv and index-shard-I-of-N.html). The merge job combines them into
# summary.json, summary.csv and index.html. `afterany` runs the merge even when some task exits
# non-zero: 1 = a clip failed its dynamics check, 2 = a clip had bad input or failed otherwise
# (the failures are recorded in the summaries). A task that was killed (time limit, preemption)
# can simply be resubmitted: it skips every clip already finished.
#
#SBATCH --job-name=retarget
#SBATCH --cpus-per-task=8
#SBATCH --mem-per-cpu=1G
#SBATCH --time=04:00:00
#SBATCH --output=retarget-%A_%a.log
set -euo pipefail

INPUT=${1:?usage: sbatch --array=1-N slurm_array.sh INPUT OUTDIR [ROBOT]}
OUTDIR=${2:?usage: sbatch --array=1-N slurm_array.sh INPUT OUTDIR [ROBOT]}
ROBOT=${3:-g1}
# Slurm numbers the tasks of --array=1-N from 1, as --shard does. SLURM_ARRAY_TASK_COUNT needs
# Slurm >= 20.02; with older versions use SLURM_ARRAY_TASK_MAX.
I=${SLURM_ARRAY_TASK_ID:?run this with sbatch --array=1-N}
N=${SLURM_ARRAY_TASK_COUNT:-${SLURM_ARRAY_TASK_MAX}}

# -j: one worker per CPU Slurm gave this task (the default, made explicit). --timeout bounds a
# clip that hangs; --memory-limit bounds each worker (MiB of address space).
exec retarget batch "$INPUT" --robot "$ROBOT" -o "$OUTDIR" --check --format csv,npz \
  --shard "$I/$N" -j "${SLURM_CPUS_PER_TASK:-1}" --timeout 1800 --memory-limit 4096
